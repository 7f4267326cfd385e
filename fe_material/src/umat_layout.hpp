#pragma once
// The PROPS layout of the UMAT entry points (umat_, pnc_umat_; docs/plugin.md "PROPS"): the
// one definition that umat.cpp reads PROPS by and that the C ABI exposes as metadata
// (pnc_material_umat_*), so `pnc card export` never keeps a second list (docs/decisions.md
// D163). Internal to the plugin.
#include "pnc/damage/ndm.hpp"

#include <array>
#include <cstddef>
#include <string>

namespace pnc::fe_material::detail {

/// PROPS(1): the model code.
constexpr double kModelCodePnc = 1.0;
constexpr double kModelCodePp = 2.0;
/// The optional platelet rotation R after the constants: 9 entries, row-major.
constexpr int kRotationEntries = 9;

inline double model_code(pnc::damage::Model m) {
  return m == pnc::damage::Model::pnc ? kModelCodePnc : kModelCodePp;
}

/// Model of a PROPS(1) value; false when it is no model code.
inline bool model_from_code(double code, pnc::damage::Model& m) {
  if (code == kModelCodePnc) {
    m = pnc::damage::Model::pnc;
    return true;
  }
  if (code == kModelCodePp) {
    m = pnc::damage::Model::pp;
    return true;
  }
  return false;
}

/// Number of constants of the model (PROPS(2..1+n)).
inline int props_constants(pnc::damage::Model m) {
  return static_cast<int>(pnc::damage::constant_names(m).size());
}

/// NPROPS without / with the rotation.
inline int props_count(pnc::damage::Model m, bool with_rotation) {
  return 1 + props_constants(m) + (with_rotation ? kRotationEntries : 0);
}

/// 0-based index of the first rotation entry.
inline int props_rotation_offset(pnc::damage::Model m) {
  return 1 + props_constants(m);
}

/// Name of PROPS(i + 1) (0-based i in [0, props_count(m, true))): "model_code", the constant
/// names of pnc::damage::constant_names(), "R11".."R33"; nullptr outside. The strings are
/// static.
inline const char* props_name(pnc::damage::Model m, int i) {
  static const std::array<const char*, kRotationEntries> kR = {"R11", "R12", "R13", "R21", "R22",
                                                               "R23", "R31", "R32", "R33"};
  const int n = props_constants(m);
  if (i == 0) return "model_code";
  if (i >= 1 && i <= n)
    return pnc::damage::constant_names(m)[static_cast<std::size_t>(i - 1)].c_str();
  if (i > n && i <= n + kRotationEntries) return kR[static_cast<std::size_t>(i - 1 - n)];
  return nullptr;
}

/// Units of PROPS(i + 1): "Pa" for the stiffness-like constants, "1" for the model code,
/// alpha and R; nullptr outside.
inline const char* props_units(pnc::damage::Model m, int i) {
  const char* name = props_name(m, i);
  if (!name) return nullptr;
  const int n = props_constants(m);
  if (i >= 1 && i <= n && std::string(name) != "alpha") return "Pa";
  return "1";
}

/// Fills props[0..props_count-1] for parameters p.
inline void fill_props(const pnc::damage::NdmParameters& p, bool with_rotation, double* props) {
  props[0] = model_code(p.model);
  const int n = props_constants(p.model);
  for (int i = 0; i < n; ++i)
    props[1 + i] = p.k[static_cast<std::size_t>(i)];
  if (with_rotation)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        props[1 + n + 3 * r + c] = p.R(r, c);
}

} // namespace pnc::fe_material::detail
