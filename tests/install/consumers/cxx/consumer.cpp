// A C++ host of the installed pnc material plugin (tests/install/check.sh, docs/install.md):
// linked through find_package(pnc) / pnc::material, and the same library loaded again with
// the header-only pnc::fe_material::Plugin. Checks, for the card built by pnc::pnc:
//  - the linked material, one made from its constants and one loaded through Plugin give
//    bitwise the same stress and state along a loading-unloading path (same code, same input);
//  - in the elastic range (strains <= 0.5 %, far below the onset stretch alpha x 1.2445)
//    stress = C0 eps, C0 assembled here from the card's C11..C66 (engineering shear);
//  - past the onset (uniaxial strain 0.15 along x1), unloading follows the damaged secant:
//    stress = eps / eps_peak x stress_peak, with a frozen state.
// Tolerances are rounding bounds (1e-12 of the stress scale, ~1e3 times double rounding).
#include <pnc/fe_material/material.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

static_assert(PNC_CONFIG_ABI == PNC_MATERIAL_ABI_VERSION,
              "pncConfig.cmake and pnc_material.h disagree on the ABI version");

namespace fm = pnc::fe_material;

namespace {

int failures = 0;

void check(bool ok, const char* what, double got, double want, double tol) {
  if (ok) return;
  std::fprintf(stderr, "FAIL %s: got %.17g, want %.17g (tolerance %.3g)\n", what, got, want, tol);
  ++failures;
}

struct Point {
  fm::Voigt6 sig;
  std::vector<double> state;
};

// eps(t) = t dir for t = 0 -> 1 -> 0 in n + n steps; every point's stress and state
std::vector<Point> drive(const fm::Material& m, const fm::Voigt6& dir, int n) {
  std::vector<Point> out;
  std::vector<double> s0 = m.initial_state(), s1;
  fm::Voigt6 eps{}, deps{}, sig{};
  for (int k = 0; k < 2 * n; ++k) {
    const double sign = k < n ? 1.0 : -1.0;
    for (int i = 0; i < 6; ++i)
      deps[i] = sign * dir[i] / n;
    m.integrate(s0, s1, eps, deps, sig);
    for (int i = 0; i < 6; ++i)
      eps[i] += deps[i];
    s0 = s1;
    out.push_back({sig, s1});
  }
  return out;
}

std::array<double, 36> elastic_stiffness(const fm::Material& m) {
  std::array<double, 36> C{};
  C[0] = m.constant("C11");
  C[7] = m.constant("C22");
  C[14] = m.constant("C33");
  C[1] = C[6] = m.constant("C12");
  C[2] = C[12] = m.constant("C13");
  C[8] = C[13] = m.constant("C23");
  C[21] = m.constant("C44"); // 23
  C[28] = m.constant("C55"); // 13
  C[35] = m.constant("C66"); // 12
  return C;
}

} // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer CARD\n");
    return 2;
  }
  try {
    const fm::Material linked = fm::Material::from_card(argv[1]);
    if (linked.model() != "pnc") throw fm::Error("expected a pnc card");
    const auto R = linked.rotation();
    const fm::Material copy = fm::Material::from_constants("pnc", linked.constants(), &R);
    const fm::Plugin plugin(PNC_PLUGIN_PATH);
    const fm::Material loaded = plugin.from_card(argv[1]);
    std::printf("card %s: verdict %s; plugin %s\n", argv[1], linked.verdict().c_str(),
                loaded.library().c_str());

    // 1. elastic range
    const fm::Voigt6 small{5e-3, -1e-3, 2e-3, -3e-3, 4e-3, 2.5e-3};
    const int n = 25;
    const auto C = elastic_stiffness(linked);
    const auto el = drive(linked, small, n);
    for (int k = 0; k < 2 * n; ++k) {
      const double t = k < n ? (k + 1.0) / n : (2.0 * n - k - 1) / n;
      for (int i = 0; i < 6; ++i) {
        double want = 0, scale = 1e-3 * 1e9;
        for (int j = 0; j < 6; ++j) {
          want += C[6 * i + j] * t * small[j];
          scale = std::max(scale, std::abs(C[6 * i + j] * small[j]));
        }
        check(std::abs(el[k].sig[i] - want) <= 1e-12 * 6 * scale, "elastic stress = C0 eps",
              el[k].sig[i], want, 1e-12 * 6 * scale);
      }
      for (int i = 3; i < 6; ++i)
        check(el[k].state[i] == 0.0, "no damage in the elastic range", el[k].state[i], 0, 0);
    }

    // 2. past the onset and back: secant unloading; all three routes identical
    const fm::Voigt6 uni{0.15, 0, 0, 0, 0, 0};
    const auto a = drive(linked, uni, 150), b = drive(copy, uni, 150), c = drive(loaded, uni, 150);
    const Point& peak = a[149];
    check(peak.state[3] > 1e-3, "damage D1 has grown past the onset", peak.state[3], 1e-3, 0);
    double smax = 0;
    for (double v : peak.sig)
      smax = std::max(smax, std::abs(v));
    for (std::size_t k = 0; k < a.size(); ++k) {
      for (int i = 0; i < 6; ++i) {
        check(a[k].sig[i] == b[k].sig[i], "from_constants = from_card", b[k].sig[i], a[k].sig[i],
              0);
        check(a[k].sig[i] == c[k].sig[i], "Plugin = linked", c[k].sig[i], a[k].sig[i], 0);
      }
      if (k < 150) continue;
      const double r = (299.0 - static_cast<double>(k)) / 150.0; // eps / eps_peak
      for (int i = 0; i < 6; ++i)
        check(std::abs(a[k].sig[i] - r * peak.sig[i]) <= 1e-12 * smax, "unloading on the secant",
              a[k].sig[i], r * peak.sig[i], 1e-12 * smax);
      for (std::size_t i = 0; i < peak.state.size(); ++i)
        check(a[k].state[i] == peak.state[i], "state frozen while unloading", a[k].state[i],
              peak.state[i], 0);
    }
    std::printf("peak: sigma11 = %.6g Pa, D1 = %.4f\n", peak.sig[0], peak.state[3]);
  } catch (const fm::Error& e) {
    std::fprintf(stderr, "FAIL: %s\n", e.what());
    return 1;
  }
  if (failures)
    std::fprintf(stderr, "%d check(s) failed\n", failures);
  else
    std::printf("c++ consumer: all checks passed\n");
  return failures ? 1 : 0;
}
