/* Compiled as C99: proves that pnc_material.h is a C header and that the ABI works from C.
 * Loads a card, drives uniaxial strain along x1 from 0 to 0.15 in 15 steps, unloads to 0.05
 * and reloads to 0.15 again (10 + 10 steps), and returns the final stress and state. */
#include "pnc/fe_material/pnc_material.h"

#include <stdio.h>
#include <string.h>

int run_c_path(const char* card, double* out_stress, double* out_state, int* out_n_state);

int run_c_path(const char* card, double* out_stress, double* out_state, int* out_n_state) {
  char err[512];
  double state0[16], state1[16];
  double strain[6] = {0, 0, 0, 0, 0, 0};
  double dstrain[6] = {0, 0, 0, 0, 0, 0};
  double stress[6];
  double tangent[PNC_MATERIAL_TANGENT_SIZE];
  const double targets[3] = {0.15, 0.05, 0.15};
  const int steps[3] = {15, 10, 10};
  pnc_material* m;
  int n, seg, k, i, status = PNC_MATERIAL_OK;

  if (pnc_material_abi_version() != PNC_MATERIAL_ABI_VERSION) return -1;
  m = pnc_material_create(card, err, sizeof err);
  if (!m) {
    fprintf(stderr, "run_c_path: %s\n", err);
    return -2;
  }
  n = pnc_material_n_state(m);
  if (n < 1 || n > 16) {
    pnc_material_destroy(m);
    return -3;
  }
  pnc_material_init_state(m, state0);
  for (seg = 0; seg < 3 && status == PNC_MATERIAL_OK; ++seg) {
    const double step = (targets[seg] - strain[0]) / steps[seg];
    for (k = 0; k < steps[seg]; ++k) {
      dstrain[0] = step;
      status = pnc_material_integrate(m, state0, state1, strain, dstrain, stress, tangent, err,
                                      sizeof err);
      if (status != PNC_MATERIAL_OK) {
        fprintf(stderr, "run_c_path: %s\n", err);
        break;
      }
      strain[0] += step;
      memcpy(state0, state1, sizeof(double) * (size_t)n);
    }
  }
  if (status == PNC_MATERIAL_OK) {
    for (i = 0; i < 6; ++i)
      out_stress[i] = stress[i];
    for (i = 0; i < n; ++i)
      out_state[i] = state0[i];
    *out_n_state = n;
  }
  pnc_material_destroy(m);
  return status;
}
