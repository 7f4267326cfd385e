/* pnc/fe_material/pnc_material.h: the fitted nano-scale damage model (NDM) as a loadable
 * material, behind a small versioned C ABI. Pure C (C99 and C++); docs/plugin.md.
 *
 * Units and conventions (the same as pnc::damage::integrate(), which does all the physics):
 *  - stress: Cauchy stress in Pa; strain: small strain, dimensionless.
 *  - Voigt order 11, 22, 33, 23, 13, 12. Strain uses ENGINEERING shear
 *    (gamma_23 = 2 eps_23, ...); stress is plain (sigma_23, ...).
 *  - tangent: 6x6, ROW-MAJOR, tangent[6*i + j] = d sigma_i / d eps_j in Pa (engineering shear
 *    strain as the independent variable). It is the consistent tangent of the increment:
 *    it includes the damage-growth term when a damage mode is loading, so it is in general
 *    NOT symmetric.
 *  - constants: SI, in the order of pnc_material_constant_name(); stiffness-like constants
 *    (C*, A*, B*) in Pa, alpha dimensionless.
 *  - platelet rotation R: 3x3 row-major, x_local = R x_global (identity when the platelet
 *    lies along the global x1 axis).
 *
 * Thread safety: a pnc_material is immutable after creation. pnc_material_integrate() and
 * all the query functions may be called on one material from many threads at once.
 * pnc_material_create() reads HDF5 with the serial HDF5 library, which is not thread-safe:
 * create materials from one thread at a time (or before starting threads).
 *
 * Errors: functions that can fail take a caller-owned buffer `err` of `errlen` bytes (may
 * be NULL/0) and write one NUL-terminated line into it that names the source (file, function
 * or argument), the field, the offending value and the rule that was broken. Nothing ever
 * throws or aborts across this interface.
 */
#ifndef PNC_FE_MATERIAL_PNC_MATERIAL_H
#define PNC_FE_MATERIAL_PNC_MATERIAL_H

#include <stddef.h>

/* Bumped on any incompatible change of the functions or the conventions above. */
#define PNC_MATERIAL_ABI_VERSION 1

#if defined(_WIN32)
#if defined(PNC_MATERIAL_BUILDING)
#define PNC_MATERIAL_API __declspec(dllexport)
#else
#define PNC_MATERIAL_API
#endif
#elif defined(__GNUC__) || defined(__clang__)
#define PNC_MATERIAL_API __attribute__((visibility("default")))
#else
#define PNC_MATERIAL_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes of pnc_material_integrate(). */
#define PNC_MATERIAL_OK 0
#define PNC_MATERIAL_BAD_INPUT 1    /* non-finite strain or state, or a non-finite result */
#define PNC_MATERIAL_BAD_ARGUMENT 2 /* NULL material or array where one is required */
#define PNC_MATERIAL_INTERNAL 3     /* unexpected failure inside the library */

/* Number of Voigt components, and of tangent entries. */
#define PNC_MATERIAL_NTENS 6
#define PNC_MATERIAL_TANGENT_SIZE 36

/* Opaque, immutable material: model, constants and platelet rotation. */
typedef struct pnc_material pnc_material;

/* The ABI version the library was built with; compare with PNC_MATERIAL_ABI_VERSION. */
PNC_MATERIAL_API int pnc_material_abi_version(void);

/* Loads a material card (HDF5, docs/formats.md) and validates it. Returns NULL on failure,
 * with the message (file, dataset, value, rule) in err. A card whose verdict is "not usable"
 * (a fit that does not describe its data, docs/formats.md) is refused with its reasons,
 * unless the environment variable PNC_ALLOW_NOT_USABLE_CARD is set to 1 (the user's explicit
 * request, for hosts that cannot pass flags) or the host calls pnc_material_create_ex(). */
PNC_MATERIAL_API pnc_material* pnc_material_create(const char* card_path, char* err, size_t errlen);

/* Flags of pnc_material_create_ex(). */
#define PNC_MATERIAL_ALLOW_NOT_USABLE 1u /* load a "not usable" card all the same */

/* pnc_material_create() with flags (a bitwise or of PNC_MATERIAL_* flags above). */
PNC_MATERIAL_API pnc_material* pnc_material_create_ex(const char* card_path, unsigned flags,
                                                      char* err, size_t errlen);

/* The verdict of the card the material came from: "usable", "usable with warnings" or
 * "not usable" ("usable" for materials made from constants). Lives as long as the material. */
PNC_MATERIAL_API const char* pnc_material_verdict(const pnc_material* m);

/* Builds a material without reading any file (no HDF5 is touched): for hosts that already
 * link another HDF5 library. model is "pnc" (nanocomposite, 22 constants) or "pp" (pure
 * polymer, 7 constants); constants[0..n-1] in the order of pnc_material_constant_name(), SI;
 * rotation9 is the platelet rotation R, row-major, x_local = R x_global, or NULL for the
 * identity. The constants are validated as a card's would be. Returns NULL on failure. */
PNC_MATERIAL_API pnc_material* pnc_material_create_from_constants(const char* model,
                                                                  const double* constants, int n,
                                                                  const double* rotation9,
                                                                  char* err, size_t errlen);

/* Frees a material (NULL is allowed). */
PNC_MATERIAL_API void pnc_material_destroy(pnc_material* m);

/* "pnc" or "pp". */
PNC_MATERIAL_API const char* pnc_material_model(const pnc_material* m);

/* The constants the material holds (names as in the card; values SI). Out-of-range indices
 * give NULL / NaN. Returned strings live as long as the material. */
PNC_MATERIAL_API int pnc_material_n_constants(const pnc_material* m);
PNC_MATERIAL_API const char* pnc_material_constant_name(const pnc_material* m, int i);
PNC_MATERIAL_API double pnc_material_constant(const pnc_material* m, int i);
/* The platelet rotation, row-major into rotation9[9]. */
PNC_MATERIAL_API void pnc_material_rotation(const pnc_material* m, double* rotation9);

/* Internal state per integration point: pnc has 6 entries (kappa1, kappa2, kappa3, D1, D2,
 * D3), pp has 2 (kappa, D). kappa_k is the largest mode stretch reached (1 = virgin; never
 * decreases), D_k the damage variable derived from it (0 = undamaged). */
PNC_MATERIAL_API int pnc_material_n_state(const pnc_material* m);
PNC_MATERIAL_API const char* pnc_material_state_name(const pnc_material* m, int i);
/* Writes the virgin state into state[0..n_state-1]. */
PNC_MATERIAL_API void pnc_material_init_state(const pnc_material* m, double* state);

/* Integrates the law over one strain increment.
 *  state0  : state at the start of the increment (n_state entries, read only)
 *  state1  : state at the end (written; may alias state0)
 *  strain0 : total strain at the start, dstrain its increment (6 each, see conventions)
 *  stress  : Cauchy stress at the end, Pa (6, written)
 *  tangent : NULL, or 36 entries for the consistent tangent (row-major, Pa)
 * Every entry of state0 must be finite, and so must every entry of the result (stress,
 * state1 and, when asked for, the tangent; a finite but huge strain can overflow); otherwise
 * PNC_MATERIAL_BAD_INPUT. umat_ applies the same checks.
 * Returns PNC_MATERIAL_OK, or another status with a message in err; on failure state1,
 * stress and tangent are not written. */
PNC_MATERIAL_API int pnc_material_integrate(const pnc_material* m, const double* state0,
                                            double* state1, const double strain0[6],
                                            const double dstrain[6], double stress[6],
                                            double* tangent, char* err, size_t errlen);

/* The UMAT PROPS of a material: the layout umat_ / pnc_umat_ read (umat.h, docs/plugin.md
 * "PROPS"), so that no host assembles PROPS by hand. PROPS(1) is the model code (1 = pnc,
 * 2 = pp), PROPS(2..1+n) the n constants (SI, order of pnc_material_constant_name()), then,
 * optionally, the 9 entries of the platelet rotation R (row-major). Without
 * PNC_MATERIAL_PROPS_WITH_ROTATION in flags, R is included only when it is not the identity.
 * Added after the first release of ABI 1: an older plugin lacks these symbols (the C++
 * wrapper then throws when they are used). */
#define PNC_MATERIAL_PROPS_WITH_ROTATION 1u
/* NPROPS for these flags (0 for a NULL material). */
PNC_MATERIAL_API int pnc_material_umat_nprops(const pnc_material* m, unsigned flags);
/* Writes NPROPS values into props[0..n-1]; returns NPROPS, or -1 (nothing written) when m or
 * props is NULL or n < NPROPS. */
PNC_MATERIAL_API int pnc_material_umat_props(const pnc_material* m, unsigned flags, double* props,
                                             int n);
/* Name ("model_code", "C11", ..., "alpha", "R11", ..., "R33") and units ("Pa" or "1") of
 * PROPS(i + 1), for 0 <= i < NPROPS with the rotation; NULL outside. Static strings. */
PNC_MATERIAL_API const char* pnc_material_umat_prop_name(const pnc_material* m, int i);
PNC_MATERIAL_API const char* pnc_material_umat_prop_units(const pnc_material* m, int i);

/* Function-pointer types, for hosts that resolve the functions with dlsym(). */
typedef int (*pnc_material_abi_version_fn)(void);
typedef pnc_material* (*pnc_material_create_fn)(const char*, char*, size_t);
typedef pnc_material* (*pnc_material_create_ex_fn)(const char*, unsigned, char*, size_t);
typedef const char* (*pnc_material_verdict_fn)(const pnc_material*);
typedef pnc_material* (*pnc_material_create_from_constants_fn)(const char*, const double*, int,
                                                               const double*, char*, size_t);
typedef void (*pnc_material_destroy_fn)(pnc_material*);
typedef const char* (*pnc_material_model_fn)(const pnc_material*);
typedef int (*pnc_material_n_constants_fn)(const pnc_material*);
typedef const char* (*pnc_material_constant_name_fn)(const pnc_material*, int);
typedef double (*pnc_material_constant_fn)(const pnc_material*, int);
typedef void (*pnc_material_rotation_fn)(const pnc_material*, double*);
typedef int (*pnc_material_n_state_fn)(const pnc_material*);
typedef const char* (*pnc_material_state_name_fn)(const pnc_material*, int);
typedef void (*pnc_material_init_state_fn)(const pnc_material*, double*);
typedef int (*pnc_material_integrate_fn)(const pnc_material*, const double*, double*, const double*,
                                         const double*, double*, double*, char*, size_t);
typedef int (*pnc_material_umat_nprops_fn)(const pnc_material*, unsigned);
typedef int (*pnc_material_umat_props_fn)(const pnc_material*, unsigned, double*, int);
typedef const char* (*pnc_material_umat_prop_name_fn)(const pnc_material*, int);
typedef const char* (*pnc_material_umat_prop_units_fn)(const pnc_material*, int);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* PNC_FE_MATERIAL_PNC_MATERIAL_H */
