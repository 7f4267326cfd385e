/* pnc/fe_material/umat.h: the Abaqus-style UMAT entry point of the pnc material plugin.
 * Pure C (C99 and C++). Layout of PROPS and STATEV: docs/plugin.md.
 *
 * Standard Abaqus/Standard UMAT argument list, everything by reference (Fortran calling
 * convention, lower-case name with one trailing underscore as gfortran and ifort emit it),
 * plus the hidden length of the CHARACTER*80 CMNAME as the last argument.
 *
 *  - STRESS, STRAN, DSTRAN: Abaqus order 11, 22, 33, 12, 13, 23 (NTENS = 6) or
 *    11, 22, 33, 12 (NTENS = 4: plane strain / axisymmetric), ENGINEERING shear strain;
 *    stress in Pa, strain dimensionless.
 *  - DDSDDE: NTENS x NTENS, column-major (Fortran), DDSDDE(i,j) = d STRESS(i) / d STRAN(j).
 *  - PROPS(1) = model code (1 = pnc, 2 = pp); PROPS(2..1+n) = the n constants in SI in the
 *    order of pnc_material_constant_name(); optionally 9 more: the platelet rotation R,
 *    row-major, x_local = R x_material.
 *  - STATEV: NSTATV must equal the model's state size (pnc 6, pp 2). A state of all zeros is
 *    read as the virgin state (Abaqus initialises STATEV to zero).
 *  - A refused call prints one line naming UMAT, the argument, the value and the rule to
 *    stderr and leaves STRESS/STATEV/DDSDDE untouched. A bad increment (non-finite STRAN,
 *    DSTRAN or STATEV, or a non-finite result) lowers PNEWDT to 0.5. A configuration error
 *    (NTENS/NDI/NSHR, NPROPS, PROPS, NSTATV, a NULL argument: the same on every increment)
 *    stops the process like Abaqus's XIT, with exit(PNC_UMAT_EXIT_CONFIG), unless the
 *    environment variable PNC_UMAT_ON_CONFIG_ERROR is "cutback": then PNEWDT = 0.5 as well.
 *
 * Two names, one function: pnc_umat_ (for a user's own UMAT that forwards to it, so the
 * plugin's symbol never clashes with the user's `umat_`) and umat_ (for hosts that call the
 * routine by its Abaqus name directly).
 */
#ifndef PNC_FE_MATERIAL_UMAT_H
#define PNC_FE_MATERIAL_UMAT_H

#include "pnc/fe_material/pnc_material.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Exit status of a configuration error in "stop" mode (EX_CONFIG of sysexits.h). */
#define PNC_UMAT_EXIT_CONFIG 78

PNC_MATERIAL_API void
pnc_umat_(double* stress, double* statev, double* ddsdde, double* sse, double* spd, double* scd,
          double* rpl, double* ddsddt, double* drplde, double* drpldt, const double* stran,
          const double* dstran, const double* time, const double* dtime, const double* temp,
          const double* dtemp, const double* predef, const double* dpred, const char* cmname,
          const int* ndi, const int* nshr, const int* ntens, const int* nstatv, const double* props,
          const int* nprops, const double* coords, const double* drot, double* pnewdt,
          const double* celent, const double* dfgrd0, const double* dfgrd1, const int* noel,
          const int* npt, const int* layer, const int* kspt, const int* kstep, const int* kinc,
          size_t cmname_len);

/* The same function under its Abaqus name. */
PNC_MATERIAL_API void umat_(double* stress, double* statev, double* ddsdde, double* sse,
                            double* spd, double* scd, double* rpl, double* ddsddt, double* drplde,
                            double* drpldt, const double* stran, const double* dstran,
                            const double* time, const double* dtime, const double* temp,
                            const double* dtemp, const double* predef, const double* dpred,
                            const char* cmname, const int* ndi, const int* nshr, const int* ntens,
                            const int* nstatv, const double* props, const int* nprops,
                            const double* coords, const double* drot, double* pnewdt,
                            const double* celent, const double* dfgrd0, const double* dfgrd1,
                            const int* noel, const int* npt, const int* layer, const int* kspt,
                            const int* kstep, const int* kinc, size_t cmname_len);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* PNC_FE_MATERIAL_UMAT_H */
