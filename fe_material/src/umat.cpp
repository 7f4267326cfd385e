// Abaqus-style UMAT shim over pnc::damage::integrate() (pnc/fe_material/umat.h,
// docs/plugin.md). No state is kept between calls: the constants come from PROPS and are
// re-validated on every call (a few dozen flops, no allocation when they are valid).
// Exported twice: as pnc_umat_ (the implementation, for a user's own UMAT wrapper) and as
// umat_ (an alias, for hosts that call the routine by its Abaqus name); docs/decisions.md D164.
#include "pnc/fe_material/umat.h"

#include "abi_util.hpp"
#include "umat_layout.hpp"

#include "pnc/core/error.hpp"
#include "pnc/damage/ndm.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

namespace {

using pnc::damage::Matrix6;
using pnc::damage::Model;
using pnc::damage::Voigt;

using pnc::fe_material::detail::kRotationEntries;

// Kernel Voigt index of each Abaqus component: Abaqus 11,22,33,12,13,23 vs kernel
// 11,22,33,23,13,12. NTENS = 4 (plane strain / axisymmetric) is 11,22,33,12.
constexpr std::array<int, 6> kMap6 = {0, 1, 2, 5, 4, 3};
constexpr std::array<int, 4> kMap4 = {0, 1, 2, 5};

struct Where {
  const int* noel;
  const int* npt;
  const char* cmname;
  std::size_t cmname_len;
};

// What a refused call is: a configuration error (layout, PROPS, NSTATV: the same on every
// increment, so a smaller one cannot cure it) or a bad increment (strain, state, result).
enum class Refusal { configuration, increment };

// How configuration errors end (docs/decisions.md D165): "stop" (default, like Abaqus's XIT:
// message, then exit(PNC_UMAT_EXIT_CONFIG)) or "cutback" (PNEWDT = 0.5 as for a bad
// increment), chosen by the environment variable PNC_UMAT_ON_CONFIG_ERROR. Read only when a
// call is refused, so accepted calls never touch the environment.
bool stop_on_configuration_error(std::string& note) {
  const char* v = std::getenv("PNC_UMAT_ON_CONFIG_ERROR");
  if (!v || !*v || std::strcmp(v, "stop") == 0) return true;
  if (std::strcmp(v, "cutback") == 0) return false;
  note = std::string(" (PNC_UMAT_ON_CONFIG_ERROR='") + v + "' is neither 'stop' nor 'cutback')";
  return true;
}

// One line to stderr, then ask Abaqus for a smaller increment, or stop the analysis.
void reject(const Where& w, double* pnewdt, const std::string& argument, const std::string& value,
            const std::string& rule, Refusal kind = Refusal::configuration) noexcept {
  bool stop = false;
  try {
    std::string name;
    if (w.cmname) {
      // CHARACTER*80, blank padded, not NUL terminated; the hidden length may come from a
      // compiler that passes it as a 32-bit int, so never trust more than 80 characters.
      const std::size_t len = std::min<std::size_t>(w.cmname_len, 80);
      for (std::size_t i = 0; i < len && w.cmname[i] != '\0'; ++i)
        name += w.cmname[i];
      while (!name.empty() && name.back() == ' ')
        name.pop_back();
    }
    std::string note;
    stop = kind == Refusal::configuration && stop_on_configuration_error(note);
    std::string line = "UMAT";
    if (!name.empty()) line += " material '" + name + "'";
    if (w.noel && w.npt)
      line += " (element " + std::to_string(*w.noel) + ", point " + std::to_string(*w.npt) + ")";
    line += ": argument '" + argument + "'";
    if (!value.empty()) line += ": value '" + value + "'";
    if (stop)
      line += ": " + rule + "; configuration error: stopping the analysis (exit status " +
              std::to_string(PNC_UMAT_EXIT_CONFIG) + note +
              "; PNC_UMAT_ON_CONFIG_ERROR=cutback requests PNEWDT = 0.5 instead)\n";
    else
      line += ": " + rule + "; requesting a smaller increment (PNEWDT = 0.5)\n";
    std::fputs(line.c_str(), stderr);
  } catch (...) {
    std::fputs("UMAT: invalid input (message could not be built); PNEWDT = 0.5\n", stderr);
  }
  if (stop) {
    std::fflush(nullptr);
    std::exit(PNC_UMAT_EXIT_CONFIG);
  }
  if (pnewdt && !(*pnewdt <= 0.5)) *pnewdt = 0.5;
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// Maps a field named by pnc::damage::validate() to the PROPS entries it came from.
std::string props_argument(Model m, const std::string& field) {
  const int i = pnc::damage::constant_index(m, field);
  if (i >= 0) return "PROPS(" + std::to_string(i + 2) + ") = " + field;
  const int n = static_cast<int>(pnc::damage::constant_names(m).size());
  if (field == "platelet_rotation")
    return "PROPS(" + std::to_string(n + 2) + ".." + std::to_string(n + 1 + kRotationEntries) +
           ") = platelet rotation R";
  return "PROPS(2.." + std::to_string(n + 1) + ") = " + field;
}

} // namespace

extern "C" PNC_MATERIAL_API void
pnc_umat_(double* stress, double* statev, double* ddsdde, double* sse, double* /*spd*/,
          double* /*scd*/, double* /*rpl*/, double* /*ddsddt*/, double* /*drplde*/,
          double* /*drpldt*/, const double* stran, const double* dstran, const double* /*time*/,
          const double* /*dtime*/, const double* /*temp*/, const double* /*dtemp*/,
          const double* /*predef*/, const double* /*dpred*/, const char* cmname, const int* ndi,
          const int* nshr, const int* ntens, const int* nstatv, const double* props,
          const int* nprops, const double* /*coords*/, const double* /*drot*/, double* pnewdt,
          const double* /*celent*/, const double* /*dfgrd0*/, const double* /*dfgrd1*/,
          const int* noel, const int* npt, const int* /*layer*/, const int* /*kspt*/,
          const int* /*kstep*/, const int* /*kinc*/, size_t cmname_len) {
  const Where w{noel, npt, cmname, cmname_len};
  try {
    if (!stress || !statev || !ddsdde || !stran || !dstran || !ndi || !nshr || !ntens || !nstatv ||
        !props || !nprops) {
      reject(w, pnewdt, "STRESS/STATEV/DDSDDE/STRAN/DSTRAN/NDI/NSHR/NTENS/NSTATV/PROPS/NPROPS",
             "NULL", "all of these must be passed");
      return;
    }
    // --- tensor layout
    const int nt = *ntens;
    if (nt != 6 && nt != 4) {
      reject(w, pnewdt, "NTENS", std::to_string(nt),
             "must be 6 (3-D) or 4 (plane strain / axisymmetric); plane stress (3) and other "
             "layouts are not supported");
      return;
    }
    const int want_nshr = nt == 6 ? 3 : 1;
    if (*ndi != 3 || *nshr != want_nshr) {
      reject(w, pnewdt, "NDI, NSHR", std::to_string(*ndi) + ", " + std::to_string(*nshr),
             "must be 3, " + std::to_string(want_nshr) + " for NTENS = " + std::to_string(nt));
      return;
    }
    const int* map = nt == 6 ? kMap6.data() : kMap4.data();

    // --- model and PROPS layout
    if (*nprops < 1) {
      reject(w, pnewdt, "NPROPS", std::to_string(*nprops),
             "must be at least 1: PROPS(1) is the model code (1 = pnc, 2 = pp)");
      return;
    }
    Model model;
    if (!pnc::fe_material::detail::model_from_code(props[0], model)) {
      reject(w, pnewdt, "PROPS(1)", num(props[0]), "the model code must be 1 (pnc) or 2 (pp)");
      return;
    }
    namespace layout = pnc::fe_material::detail;
    const auto& names = pnc::damage::constant_names(model);
    const int n = layout::props_constants(model);
    const bool with_rotation = *nprops == layout::props_count(model, true);
    if (*nprops != layout::props_count(model, false) && !with_rotation) {
      reject(w, pnewdt, "NPROPS", std::to_string(*nprops),
             std::string("model ") + pnc::damage::model_name(model) + " needs " +
                 std::to_string(n + 1) + " (model code + " + std::to_string(n) + " constants " +
                 names.front() + ".." + names.back() + ") or " +
                 std::to_string(n + 1 + kRotationEntries) + " (plus the platelet rotation R)");
      return;
    }
    const int ns = static_cast<int>(pnc::damage::state_size(model));
    if (*nstatv != ns) {
      reject(w, pnewdt, "NSTATV", std::to_string(*nstatv),
             std::string("model ") + pnc::damage::model_name(model) + " has " + std::to_string(ns) +
                 " state variables (" +
                 (model == Model::pnc ? "kappa1 kappa2 kappa3 D1 D2 D3" : "kappa D") + ")");
      return;
    }
    pnc::damage::NdmParameters p;
    p.model = model;
    for (int i = 0; i < n; ++i)
      p.k[static_cast<std::size_t>(i)] = props[1 + i];
    if (with_rotation)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          p.R(r, c) = props[layout::props_rotation_offset(model) + 3 * r + c];
    try {
      pnc::damage::validate(p, "UMAT PROPS");
    } catch (const pnc::InputError& e) {
      reject(w, pnewdt, props_argument(model, e.context().field), e.context().value,
             e.context().rule);
      return;
    }

    // --- strain and state
    Voigt e0 = Voigt::Zero(), de = Voigt::Zero();
    for (int a = 0; a < nt; ++a) {
      if (!std::isfinite(stran[a]) || !std::isfinite(dstran[a])) {
        reject(w, pnewdt,
               "STRAN(" + std::to_string(a + 1) + ") / DSTRAN(" + std::to_string(a + 1) + ")",
               num(stran[a]) + " / " + num(dstran[a]), "strains must be finite",
               Refusal::increment);
        return;
      }
      e0[map[a]] = stran[a];
      de[map[a]] = dstran[a];
    }
    if (const auto bad = pnc::fe_material::detail::check_state(statev, ns)) {
      reject(w, pnewdt, "STATEV(" + std::to_string(bad.index + 1) + ")", num(bad.value), bad.rule,
             Refusal::increment);
      return;
    }
    std::array<double, 6> sv{};
    for (int i = 0; i < ns; ++i)
      sv[static_cast<std::size_t>(i)] = statev[i];
    // Abaqus starts STATEV at zero: a zero kappa means "never loaded" (kappa = 1).
    const int nk = model == Model::pnc ? 3 : 1;
    for (int k = 0; k < nk; ++k)
      if (sv[static_cast<std::size_t>(k)] == 0.0) sv[static_cast<std::size_t>(k)] = 1.0;

    // --- the physics: one kernel call
    const pnc::damage::NdmState s0 = pnc::damage::state_from_array(model, sv.data());
    pnc::damage::NdmState s1;
    Voigt sigma;
    Matrix6 K;
    pnc::damage::ErrorBuffer err;
    if (pnc::damage::integrate(p, s0, s1, e0, de, sigma, &K, err) != pnc::damage::Status::ok) {
      reject(w, pnewdt, "STRAN + DSTRAN", "", err.msg, Refusal::increment);
      return;
    }

    // --- nothing reaches Abaqus unless it is finite (the same check as the C ABI)
    std::array<double, 6> sv1{};
    pnc::damage::state_to_array(model, s1, sv1.data());
    if (const auto bad =
            pnc::fe_material::detail::check_result(sigma.data(), sv1.data(), ns, K.data())) {
      const std::string what = std::string(bad.what) == "stress"  ? "STRESS"
                               : std::string(bad.what) == "state" ? "STATEV"
                                                                  : "DDSDDE";
      reject(w, pnewdt, what + " (result of STRAN + DSTRAN)", num(bad.value), bad.rule,
             Refusal::increment);
      return;
    }

    // --- back to Abaqus order; DDSDDE column-major
    for (int a = 0; a < nt; ++a) {
      stress[a] = sigma[map[a]];
      for (int b = 0; b < nt; ++b)
        ddsdde[a + b * nt] = K(map[a], map[b]);
    }
    for (int i = 0; i < ns; ++i)
      statev[i] = sv1[static_cast<std::size_t>(i)];
    if (sse) *sse = 0.5 * sigma.dot(e0 + de); // secant (damaged) elastic energy density
  } catch (const std::exception& e) {
    reject(w, pnewdt, "(internal)", "", e.what(), Refusal::increment);
  } catch (...) {
    reject(w, pnewdt, "(internal)", "", "unknown error", Refusal::increment);
  }
}

// The Abaqus name: the same function (an alias, no second copy), for hosts that call `umat`.
extern "C" PNC_MATERIAL_API void
umat_(double* stress, double* statev, double* ddsdde, double* sse, double* spd, double* scd,
      double* rpl, double* ddsddt, double* drplde, double* drpldt, const double* stran,
      const double* dstran, const double* time, const double* dtime, const double* temp,
      const double* dtemp, const double* predef, const double* dpred, const char* cmname,
      const int* ndi, const int* nshr, const int* ntens, const int* nstatv, const double* props,
      const int* nprops, const double* coords, const double* drot, double* pnewdt,
      const double* celent, const double* dfgrd0, const double* dfgrd1, const int* noel,
      const int* npt, const int* layer, const int* kspt, const int* kstep, const int* kinc,
      size_t cmname_len) __attribute__((alias("pnc_umat_")));
