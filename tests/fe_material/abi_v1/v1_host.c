/* A host program of ABI 1.0: compiled (C99) against pnc_material_v1.h, a frozen copy of
 * pnc_material.h as ABI 1.0 shipped it, and linked to the current libpnc_material. It proves
 * that a program built before ABI 1.1 links and runs unchanged (D213); the test
 * FeMaterialAbi.AHostBuiltAgainstTheV1HeaderRunsWithTheSameResults compares its numbers with
 * the same path through pnc_material_integrate2.
 *
 *   v1_host MODEL C1 C2 ... Cn      (constants SI, in the order of the model)
 *
 * drives laterally constrained extension along x2 to 0.25, unloads to 0.1 and reloads to 0.25
 * (15 + 10 + 10 increments) and prints "abi A n_state N stress s1..s6 state k1..kN" with every
 * number to 17 significant digits. Exit status 0 on success. */
#include "pnc_material_v1.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char** argv) {
  char err[512];
  double constants[32], state0[16], state1[16];
  double strain[6] = {0, 0, 0, 0, 0, 0}, dstrain[6] = {0, 0, 0, 0, 0, 0};
  double stress[6], tangent[PNC_MATERIAL_TANGENT_SIZE];
  const double targets[3] = {0.25, 0.1, 0.25};
  const int steps[3] = {15, 10, 10};
  pnc_material* m;
  int n, i, seg, k, nc = argc - 2;

  if (argc < 3 || nc > 32) {
    fprintf(stderr, "usage: v1_host MODEL C1 ... Cn\n");
    return 2;
  }
  for (i = 0; i < nc; ++i)
    constants[i] = strtod(argv[2 + i], NULL);
  m = pnc_material_create_from_constants(argv[1], constants, nc, NULL, err, sizeof err);
  if (!m) {
    fprintf(stderr, "v1_host: %s\n", err);
    return 1;
  }
  n = pnc_material_n_state(m);
  pnc_material_init_state(m, state0);
  for (seg = 0; seg < 3; ++seg) {
    const double step = (targets[seg] - strain[1]) / steps[seg];
    for (k = 0; k < steps[seg]; ++k) {
      dstrain[1] = step;
      if (pnc_material_integrate(m, state0, state1, strain, dstrain, stress, tangent, err,
                                 sizeof err) != PNC_MATERIAL_OK) {
        fprintf(stderr, "v1_host: %s\n", err);
        pnc_material_destroy(m);
        return 1;
      }
      strain[1] += step;
      memcpy(state0, state1, sizeof(double) * (size_t)n);
    }
  }
  printf("abi %d n_state %d\nstress", pnc_material_abi_version(), n);
  for (i = 0; i < 6; ++i)
    printf(" %.17g", stress[i]);
  printf("\nstate");
  for (i = 0; i < n; ++i)
    printf(" %.17g", state0[i]);
  printf("\n");
  pnc_material_destroy(m);
  return 0;
}
