// The C ABI of the pnc material plugin (pnc/fe_material/pnc_material.h). All physics is
// pnc::damage::integrate(); this file only converts arrays and errors at the C boundary.
#include "pnc/fe_material/pnc_material.h"

#include "abi_util.hpp"
#include "material_impl.hpp"
#include "umat_layout.hpp"

#include "pnc/core/error.hpp"
#include "pnc/damage/card.hpp"
#include "pnc/damage/ndm.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <new>
#include <string>

namespace {

using pnc::fe_material::detail::copy_message;

constexpr const char* kFromConstants = "pnc_material_create_from_constants";

// Runs f() and turns any exception into a message; returns the material or nullptr.
template <class F> pnc_material* guarded_create(F&& f, char* err, std::size_t errlen) noexcept {
  try {
    return f();
  } catch (const std::bad_alloc&) {
    copy_message(err, errlen, "pnc_material: out of memory");
  } catch (const std::exception& e) {
    copy_message(err, errlen, e.what());
  } catch (...) {
    copy_message(err, errlen, "pnc_material: unknown error while creating the material");
  }
  return nullptr;
}

} // namespace

extern "C" {

PNC_MATERIAL_API int pnc_material_abi_version(void) {
  return PNC_MATERIAL_ABI_VERSION;
}

PNC_MATERIAL_API pnc_material* pnc_material_create_ex(const char* card_path, unsigned flags,
                                                      char* err, size_t errlen) {
  return guarded_create(
      [&]() -> pnc_material* {
        if (!card_path)
          pnc::fail("pnc_material_create", "card_path", "NULL", "a card file path is required");
        // A clearer message than HDF5's for the most common mistake.
        if (std::FILE* probe = std::fopen(card_path, "rb"))
          std::fclose(probe);
        else
          pnc::fail(card_path, "card_path", card_path,
                    std::string("cannot open the material card: ") + std::strerror(errno));
        pnc::damage::Card card = pnc::damage::read_card(card_path); // validates
        if (card.verdict.level == pnc::damage::VerdictLevel::not_usable &&
            !(flags & PNC_MATERIAL_ALLOW_NOT_USABLE)) {
          std::string why;
          for (const auto& r : card.verdict.reasons)
            if (r.rfind("not usable: ", 0) == 0) why += (why.empty() ? "" : "; ") + r.substr(12);
          pnc::fail(card_path, "/verdict@level", "not usable",
                    "the card's fit does not describe its data (" + why +
                        "); refit it, or load it deliberately with PNC_ALLOW_NOT_USABLE_CARD=1 "
                        "or pnc_material_create_ex(..., PNC_MATERIAL_ALLOW_NOT_USABLE, ...)");
        }
        auto m = std::make_unique<pnc_material>(); // no leak if a step below throws
        m->kernel = pnc::damage::prepare(card.params);
        m->source = card_path;
        m->verdict = pnc::damage::verdict_name(card.verdict.level);
        return m.release();
      },
      err, errlen);
}

PNC_MATERIAL_API pnc_material* pnc_material_create(const char* card_path, char* err,
                                                   size_t errlen) {
  const char* allow = std::getenv("PNC_ALLOW_NOT_USABLE_CARD");
  const bool yes = allow && std::strcmp(allow, "1") == 0;
  return pnc_material_create_ex(card_path, yes ? PNC_MATERIAL_ALLOW_NOT_USABLE : 0u, err, errlen);
}

PNC_MATERIAL_API const char* pnc_material_verdict(const pnc_material* m) {
  return m ? m->verdict.c_str() : "";
}

PNC_MATERIAL_API pnc_material* pnc_material_create_from_constants(const char* model,
                                                                  const double* constants, int n,
                                                                  const double* rotation9,
                                                                  char* err, size_t errlen) {
  return guarded_create(
      [&]() -> pnc_material* {
        if (!model) pnc::fail(kFromConstants, "model", "NULL", "must be 'pnc' or 'pp'");
        pnc::damage::NdmParameters p;
        p.model = pnc::damage::parse_model(model, kFromConstants);
        const auto& names = pnc::damage::constant_names(p.model);
        const int want = static_cast<int>(names.size());
        if (n != want) {
          std::string list;
          for (const auto& s : names)
            list += (list.empty() ? "" : " ") + s;
          pnc::fail(kFromConstants, "n", std::to_string(n),
                    std::string("model ") + model + " takes " + std::to_string(want) +
                        " constants: " + list);
        }
        if (!constants) pnc::fail(kFromConstants, "constants", "NULL", "an array is required");
        for (int i = 0; i < n; ++i)
          p.k[static_cast<std::size_t>(i)] = constants[i];
        if (rotation9)
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
              p.R(r, c) = rotation9[3 * r + c];
        pnc::damage::validate(p, kFromConstants);
        auto m = std::make_unique<pnc_material>(); // no leak if a step below throws
        m->kernel = pnc::damage::prepare(p);
        m->source = "<constants>";
        return m.release();
      },
      err, errlen);
}

PNC_MATERIAL_API void pnc_material_destroy(pnc_material* m) {
  delete m;
}

PNC_MATERIAL_API const char* pnc_material_model(const pnc_material* m) {
  return m ? pnc::damage::model_name(m->kernel.p.model) : nullptr;
}

PNC_MATERIAL_API int pnc_material_n_constants(const pnc_material* m) {
  return m ? static_cast<int>(m->kernel.p.size()) : 0;
}

PNC_MATERIAL_API const char* pnc_material_constant_name(const pnc_material* m, int i) {
  if (!m || i < 0 || i >= pnc_material_n_constants(m)) return nullptr;
  return pnc::damage::constant_names(m->kernel.p.model)[static_cast<std::size_t>(i)].c_str();
}

PNC_MATERIAL_API double pnc_material_constant(const pnc_material* m, int i) {
  if (!m || i < 0 || i >= pnc_material_n_constants(m))
    return std::numeric_limits<double>::quiet_NaN();
  return m->kernel.p.k[static_cast<std::size_t>(i)];
}

PNC_MATERIAL_API void pnc_material_rotation(const pnc_material* m, double* rotation9) {
  if (!m || !rotation9) return;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      rotation9[3 * r + c] = m->kernel.p.R(r, c);
}

PNC_MATERIAL_API int pnc_material_n_state(const pnc_material* m) {
  return m ? static_cast<int>(pnc::damage::state_size(m->kernel.p.model)) : 0;
}

PNC_MATERIAL_API const char* pnc_material_state_name(const pnc_material* m, int i) {
  if (!m || i < 0 || i >= pnc_material_n_state(m)) return nullptr;
  return pnc::damage::state_names(m->kernel.p.model)[static_cast<std::size_t>(i)].c_str();
}

PNC_MATERIAL_API void pnc_material_init_state(const pnc_material* m, double* state) {
  if (!m || !state) return;
  pnc::damage::state_to_array(m->kernel.p.model, pnc::damage::NdmState{}, state);
}

PNC_MATERIAL_API int pnc_material_integrate(const pnc_material* m, const double* state0,
                                            double* state1, const double strain0[6],
                                            const double dstrain[6], double stress[6],
                                            double* tangent, char* err, size_t errlen) {
  try {
    if (!m || !state0 || !state1 || !strain0 || !dstrain || !stress) {
      copy_message(err, errlen,
                   "pnc_material_integrate: argument 'm/state0/state1/strain0/dstrain/stress': "
                   "value 'NULL': these pointers are required");
      return PNC_MATERIAL_BAD_ARGUMENT;
    }
    const pnc::damage::Model model = m->kernel.p.model;
    const int ns = static_cast<int>(pnc::damage::state_size(model));
    if (const auto bad = pnc::fe_material::detail::check_state(state0, ns)) {
      char line[512];
      std::snprintf(line, sizeof line,
                    "pnc_material_integrate: argument 'state0[%d]': value '%g': %s", bad.index,
                    bad.value, bad.rule);
      copy_message(err, errlen, line);
      return PNC_MATERIAL_BAD_INPUT;
    }
    const pnc::damage::NdmState s0 = pnc::damage::state_from_array(model, state0);
    pnc::damage::NdmState s1;
    pnc::damage::ErrorBuffer ebuf;
    // The result goes to local arrays first and reaches the caller only when it is finite, so
    // on failure state1, stress and tangent are untouched, as the header promises.
    double sig[6], K[36], st1[6];
    const pnc::damage::Status st = pnc::damage::integrate_row_major(
        m->kernel, s0, s1, strain0, dstrain, sig, tangent ? K : nullptr, ebuf);
    if (st != pnc::damage::Status::ok) {
      char line[512];
      std::snprintf(line, sizeof line,
                    "pnc_material_integrate: argument 'strain0 + dstrain': value '%g %g %g %g "
                    "%g %g': %s",
                    strain0[0] + dstrain[0], strain0[1] + dstrain[1], strain0[2] + dstrain[2],
                    strain0[3] + dstrain[3], strain0[4] + dstrain[4], strain0[5] + dstrain[5],
                    ebuf.msg);
      copy_message(err, errlen, line);
      return PNC_MATERIAL_BAD_INPUT;
    }
    pnc::damage::state_to_array(model, s1, st1);
    if (const auto bad =
            pnc::fe_material::detail::check_result(sig, st1, ns, tangent ? K : nullptr)) {
      char line[512];
      std::snprintf(line, sizeof line,
                    "pnc_material_integrate: result '%s[%d]' of strain0 + dstrain '%g %g %g %g %g "
                    "%g': value '%g': %s",
                    bad.what, bad.index, strain0[0] + dstrain[0], strain0[1] + dstrain[1],
                    strain0[2] + dstrain[2], strain0[3] + dstrain[3], strain0[4] + dstrain[4],
                    strain0[5] + dstrain[5], bad.value, bad.rule);
      copy_message(err, errlen, line);
      return PNC_MATERIAL_BAD_INPUT;
    }
    std::memcpy(stress, sig, sizeof sig);
    if (tangent) std::memcpy(tangent, K, sizeof K);
    std::memcpy(state1, st1, static_cast<std::size_t>(ns) * sizeof(double));
    return PNC_MATERIAL_OK;
  } catch (const std::exception& e) {
    copy_message(err, errlen, e.what());
  } catch (...) {
    copy_message(err, errlen, "pnc_material_integrate: unknown internal error");
  }
  return PNC_MATERIAL_INTERNAL;
}

// ---- UMAT PROPS metadata: all from umat_layout.hpp, the layout umat.cpp reads.
namespace {
bool props_with_rotation(const pnc_material* m, unsigned flags) {
  return (flags & PNC_MATERIAL_PROPS_WITH_ROTATION) || m->kernel.rotated;
}
} // namespace

PNC_MATERIAL_API int pnc_material_umat_nprops(const pnc_material* m, unsigned flags) {
  if (!m) return 0;
  return pnc::fe_material::detail::props_count(m->kernel.p.model, props_with_rotation(m, flags));
}

PNC_MATERIAL_API int pnc_material_umat_props(const pnc_material* m, unsigned flags, double* props,
                                             int n) {
  const int want = pnc_material_umat_nprops(m, flags);
  if (!m || !props || n < want) return -1;
  pnc::fe_material::detail::fill_props(m->kernel.p, props_with_rotation(m, flags), props);
  return want;
}

PNC_MATERIAL_API const char* pnc_material_umat_prop_name(const pnc_material* m, int i) {
  return m ? pnc::fe_material::detail::props_name(m->kernel.p.model, i) : nullptr;
}

PNC_MATERIAL_API const char* pnc_material_umat_prop_units(const pnc_material* m, int i) {
  return m ? pnc::fe_material::detail::props_units(m->kernel.p.model, i) : nullptr;
}

} // extern "C"
