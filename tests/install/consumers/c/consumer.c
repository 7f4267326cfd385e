/* A C host of the installed pnc material plugin, built with pkg-config only
 * (tests/install/check.sh, docs/install.md). For each card given on the command line it
 * drives the plugin's C ABI along two strain paths and checks the stress against references
 * computed here from the card's constants, not from the kernel:
 *  1. a multiaxial path in the elastic range (all strains <= 0.6 %, far below the damage
 *     onset stretch alpha x 1.2445): stress = C0 eps and tangent = C0, with C0 assembled here
 *     from C11..C66 (orthotropic, "pnc") or C11, C12, C44 (isotropic, "pp"), engineering shear;
 *  2. a uniaxial-strain path past the onset, then unloading to zero and reloading: once damage
 *     has grown, unloading is linear through the origin (the damaged secant; stress =
 *     eps / eps_peak x stress_peak), the state does not change, the tangent's driven column is
 *     stress_peak / eps_peak, and reloading returns to stress_peak.
 * Tolerances are rounding bounds: each stress component is a sum of at most 6 products of
 * ~1e9 Pa by ~1e-2, evaluated in double precision, so 1e-12 of the stress scale is ~1e3 times
 * the rounding error. Exit status 0 only if every check passes.
 * usage: consumer CARD... */
#include <pnc/fe_material/pnc_material.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

static int failures = 0;

static void check(int ok, const char* what, double got, double want, double tol) {
  if (!ok) {
    fprintf(stderr, "FAIL %s: got %.17g, want %.17g (tolerance %.3g)\n", what, got, want, tol);
    ++failures;
  }
}

static double constant(const pnc_material* m, const char* name) {
  for (int i = 0; i < pnc_material_n_constants(m); ++i)
    if (strcmp(pnc_material_constant_name(m, i), name) == 0) return pnc_material_constant(m, i);
  fprintf(stderr, "FAIL: model %s has no constant %s\n", pnc_material_model(m), name);
  ++failures;
  return NAN;
}

/* [C0] in the plugin's Voigt order 11,22,33,23,13,12 (docs/plugin.md "Constants"). */
static void elastic_stiffness(const pnc_material* m, double C[36]) {
  memset(C, 0, 36 * sizeof(double));
  if (strcmp(pnc_material_model(m), "pnc") == 0) {
    C[0] = constant(m, "C11");
    C[7] = constant(m, "C22");
    C[14] = constant(m, "C33");
    C[1] = C[6] = constant(m, "C12");
    C[2] = C[12] = constant(m, "C13");
    C[8] = C[13] = constant(m, "C23");
    C[21] = constant(m, "C44");
    C[28] = constant(m, "C55");
    C[35] = constant(m, "C66");
  } else {
    const double c11 = constant(m, "C11"), c12 = constant(m, "C12"), c44 = constant(m, "C44");
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        C[6 * i + j] = i == j ? c11 : c12;
      C[6 * (3 + i) + 3 + i] = c44;
    }
  }
}

static int step(const pnc_material* m, double* s0, const double eps0[6], const double deps[6],
                double sig[6], double K[36]) {
  char err[512];
  double s1[8];
  if (pnc_material_integrate(m, s0, s1, eps0, deps, sig, K, err, sizeof err) != PNC_MATERIAL_OK) {
    fprintf(stderr, "FAIL integrate: %s\n", err);
    ++failures;
    return 0;
  }
  memcpy(s0, s1, (size_t)pnc_material_n_state(m) * sizeof(double));
  return 1;
}

static void elastic_path(const pnc_material* m) {
  double C[36], s[8], eps[6] = {0}, sig[6], K[36], cmax = 0;
  const double dir[6] = {4e-3, -2e-3, 3e-3, 5e-3, -4e-3, 6e-3};
  const int n = 20, ns = pnc_material_n_state(m), nk = ns == 6 ? 3 : 1;
  elastic_stiffness(m, C);
  for (int i = 0; i < 36; ++i)
    cmax = fmax(cmax, fabs(C[i]));
  pnc_material_init_state(m, s);
  for (int k = 1; k <= n; ++k) {
    double deps[6];
    for (int i = 0; i < 6; ++i)
      deps[i] = dir[i] / n;
    if (!step(m, s, eps, deps, sig, K)) return;
    for (int i = 0; i < 6; ++i)
      eps[i] += deps[i];
    for (int i = 0; i < 6; ++i) {
      double want = 0, scale = 0;
      for (int j = 0; j < 6; ++j) {
        want += C[6 * i + j] * eps[j];
        scale += fabs(C[6 * i + j] * eps[j]);
      }
      const double tol = 1e-12 * fmax(scale, cmax * 1e-3);
      check(fabs(sig[i] - want) <= tol, "elastic stress = C0 eps", sig[i], want, tol);
      for (int j = 0; j < 6; ++j)
        check(fabs(K[6 * i + j] - C[6 * i + j]) <= 1e-12 * cmax, "elastic tangent = C0",
              K[6 * i + j], C[6 * i + j], 1e-12 * cmax);
    }
    for (int i = nk; i < ns; ++i) /* the damage variables stay exactly zero */
      check(s[i] == 0.0, "no damage in the elastic range", s[i], 0.0, 0.0);
  }
}

static void secant_path(const pnc_material* m, int driven, double peak) {
  const int n = 150, ns = pnc_material_n_state(m), nk = ns == 6 ? 3 : 1;
  double s[8], speak[8], eps[6] = {0}, deps[6] = {0}, sig[6], K[36], sigpeak[6];
  pnc_material_init_state(m, s);
  deps[driven] = peak / n;
  for (int k = 0; k < n; ++k) {
    if (!step(m, s, eps, deps, sig, K)) return;
    eps[driven] += deps[driven];
  }
  memcpy(sigpeak, sig, sizeof sig);
  memcpy(speak, s, sizeof s);
  double dmax = 0;
  for (int i = nk; i < ns; ++i)
    dmax = fmax(dmax, s[i]);
  check(dmax > 1e-3, "damage has grown past the onset", dmax, 1e-3, 0);
  double smax = 0;
  for (int i = 0; i < 6; ++i)
    smax = fmax(smax, fabs(sigpeak[i]));
  const double epeak = eps[driven];
  deps[driven] = -peak / n;
  for (int k = 0; k < n; ++k) { /* unload to zero */
    if (!step(m, s, eps, deps, sig, K)) return;
    eps[driven] += deps[driven];
    const double r = eps[driven] / epeak;
    for (int i = 0; i < 6; ++i) {
      check(fabs(sig[i] - r * sigpeak[i]) <= 1e-12 * smax, "unloading on the secant", sig[i],
            r * sigpeak[i], 1e-12 * smax);
      check(fabs(K[6 * i + driven] - sigpeak[i] / epeak) <= 1e-10 * smax / epeak,
            "unloading tangent = secant", K[6 * i + driven], sigpeak[i] / epeak,
            1e-10 * smax / epeak);
    }
    for (int i = 0; i < ns; ++i)
      check(s[i] == speak[i], "state frozen while unloading", s[i], speak[i], 0);
  }
  deps[driven] = peak / n;
  for (int k = 0; k < n; ++k) { /* reload to the previous peak */
    if (!step(m, s, eps, deps, sig, K)) return;
    eps[driven] += deps[driven];
  }
  for (int i = 0; i < 6; ++i)
    check(fabs(sig[i] - sigpeak[i]) <= 1e-10 * smax, "reloading returns to the peak", sig[i],
          sigpeak[i], 1e-10 * smax);
  printf("%s: peak eps%d = %.3f sigma = %.6g Pa, max D = %.4f\n", pnc_material_model(m), driven + 1,
         epeak, sigpeak[driven], dmax);
}

int main(int argc, char** argv) {
  if (pnc_material_abi_version() != PNC_MATERIAL_ABI_VERSION) {
    fprintf(stderr, "FAIL: library ABI %d, header ABI %d\n", pnc_material_abi_version(),
            PNC_MATERIAL_ABI_VERSION);
    return 1;
  }
  if (argc < 2) {
    fprintf(stderr, "usage: consumer CARD...\n");
    return 2;
  }
  for (int a = 1; a < argc; ++a) {
    char err[512];
    pnc_material* m = pnc_material_create(argv[a], err, sizeof err);
    if (!m) {
      fprintf(stderr, "FAIL %s: %s\n", argv[a], err);
      return 1;
    }
    const int pnc = strcmp(pnc_material_model(m), "pnc") == 0;
    printf("%s: model %s, verdict %s\n", argv[a], pnc_material_model(m), pnc_material_verdict(m));
    elastic_path(m);
    /* pnc: extension x1 (mode 1); pp: extension x2 (its case 2), past its later onset */
    secant_path(m, pnc ? 0 : 1, pnc ? 0.15 : 0.3);
    pnc_material_destroy(m);
  }
  if (failures)
    fprintf(stderr, "%d check(s) failed\n", failures);
  else
    printf("c consumer: all checks passed\n");
  return failures ? 1 : 0;
}
