#pragma once
// pnc/fe_material/material_api.hpp: the error type and the C function table behind the
// header-only C++ wrapper pnc/fe_material/material.hpp, which includes this header (include
// that one). Units and Voigt order as in pnc_material.h: Pa, 11,22,33,23,13,12, engineering
// shear strain.
#include "pnc/fe_material/pnc_material.h"

#include <dlfcn.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace pnc::fe_material {

/// Every failure of the wrapper (card, constants, plugin loading, integration).
class Error : public std::runtime_error {
public:
  explicit Error(const std::string& what, int status = 0)
      : std::runtime_error(what), status_(status) {}
  /// PNC_MATERIAL_* status of a failed integration; 0 for other errors.
  int status() const noexcept { return status_; }

private:
  int status_;
};

/// The C functions of one library: the linked one or a dlopen()ed plugin.
struct Api {
  pnc_material_abi_version_fn abi_version = nullptr;
  pnc_material_create_fn create = nullptr;
  pnc_material_create_ex_fn create_ex = nullptr;
  pnc_material_verdict_fn verdict = nullptr;
  pnc_material_create_from_constants_fn create_from_constants = nullptr;
  pnc_material_destroy_fn destroy = nullptr;
  pnc_material_model_fn model = nullptr;
  pnc_material_n_constants_fn n_constants = nullptr;
  pnc_material_constant_name_fn constant_name = nullptr;
  pnc_material_constant_fn constant = nullptr;
  pnc_material_rotation_fn rotation = nullptr;
  pnc_material_n_state_fn n_state = nullptr;
  pnc_material_state_name_fn state_name = nullptr;
  pnc_material_init_state_fn init_state = nullptr;
  pnc_material_integrate_fn integrate = nullptr;
  // UMAT PROPS metadata: optional (added within ABI 1; null for an older plugin)
  pnc_material_umat_nprops_fn umat_nprops = nullptr;
  pnc_material_umat_props_fn umat_props = nullptr;
  pnc_material_umat_prop_name_fn umat_prop_name = nullptr;
  pnc_material_umat_prop_units_fn umat_prop_units = nullptr;
  // ABI 1.1 (null for a plugin older than minor 1; the methods that need them throw)
  pnc_material_abi_version_minor_fn abi_version_minor = nullptr;
  pnc_material_integrate2_fn integrate2 = nullptr;
  pnc_material_property_fn property = nullptr;
  pnc_material_n_properties_fn n_properties = nullptr;
  pnc_material_property_name_fn property_name = nullptr;
  pnc_material_property_units_fn property_units = nullptr;
  pnc_material_elastic_stiffness_fn elastic_stiffness = nullptr;
  pnc_material_damage_stiffness_fn damage_stiffness = nullptr;
  pnc_material_state_index_fn state_index = nullptr;
  pnc_material_model_n_constants_fn model_n_constants = nullptr;
  pnc_material_model_constant_name_fn model_constant_name = nullptr;
  // ABI 1.2 (null for a plugin older than minor 2; integrate_batch() then throws)
  pnc_material_integrate_batch_fn integrate_batch = nullptr;
  // ABI 1.3 (null for a plugin older than minor 3; damage_of_stretch() then throws)
  pnc_material_damage_of_stretch_fn damage_of_stretch = nullptr;
  pnc_material_mode_stretch_fn mode_stretch = nullptr;
  /// All of ABI 1.1 is there.
  bool has_v2() const noexcept {
    return abi_version_minor && integrate2 && property && n_properties && property_name &&
           property_units && elastic_stiffness && damage_stiffness && state_index &&
           model_n_constants && model_constant_name;
  }
};

namespace detail {

/// A library handle (null for the linked library) and its function table.
struct Library {
  std::string path; ///< "<linked>" or the plugin path
  void* handle = nullptr;
  Api api;
  Library() = default;
  Library(const Library&) = delete;
  Library& operator=(const Library&) = delete;
  ~Library() {
    if (handle) dlclose(handle);
  }
};

inline std::string str(const char* s) {
  return s ? std::string(s) : std::string();
}

/// Throws when the library lacks ABI 1.1 (`what` names the function the caller needs).
inline void require_v2(const Library& lib, const char* what) {
  if (!lib.api.has_v2())
    throw Error("pnc::fe_material: '" + lib.path + "': symbol '" + what +
                "' is missing: the plugin predates ABI " +
                std::to_string(PNC_MATERIAL_ABI_VERSION) +
                ".1 (pnc_material_integrate2 and the property queries); use a newer "
                "libpnc_material");
}

/// The constant names of a model through a library's ABI 1.1 query.
inline std::vector<std::string> model_constant_names(const Library& lib, const std::string& model) {
  require_v2(lib, "pnc_material_model_constant_name");
  const int n = lib.api.model_n_constants(model.c_str());
  if (n == 0)
    throw Error("pnc::fe_material: field 'model': value '" + model +
                "': must be 'pnc' (nanocomposite) or 'pp' (pure polymer)");
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i)
    out.push_back(str(lib.api.model_constant_name(model.c_str(), i)));
  return out;
}

} // namespace detail

} // namespace pnc::fe_material
