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
 *  - On bad input one line naming UMAT, the argument, the value and the rule goes to stderr,
 *    PNEWDT is lowered to 0.5 and STRESS/STATEV/DDSDDE are left untouched.
 */
#ifndef PNC_FE_MATERIAL_UMAT_H
#define PNC_FE_MATERIAL_UMAT_H

#include "pnc/fe_material/pnc_material.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

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
