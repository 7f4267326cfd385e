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
#include <stdint.h>

/* The ABI version, written here and nowhere else (docs/decisions.md D153, D213).
 * MAJOR: bumped on any incompatible change of the functions or the conventions above; it is
 * the soname (libpnc_material.so.MAJOR) and pnc_material_abi_version().
 * MINOR: bumped when functions are added compatibly (a program built against MAJOR.m runs
 * with any library MAJOR.n, n >= m); the library file is libpnc_material.so.MAJOR.MINOR and
 * the symbols added in MINOR carry the symbol version PNC_MATERIAL_MAJOR.MINOR.
 * 1.0: the first ABI (pnc_material_integrate, the queries, UMAT PROPS metadata).
 * 1.1: the v2 point interface (pnc_material_point, pnc_material_integrate2), property and
 *      state-index queries.
 * 1.2: the batched entry (pnc_material_point_soa, pnc_material_integrate_batch). */
#define PNC_MATERIAL_ABI_VERSION 1
#define PNC_MATERIAL_ABI_VERSION_MINOR 3

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

/* Status codes of pnc_material_integrate(), pnc_material_integrate2() and the queries. */
#define PNC_MATERIAL_OK 0
#define PNC_MATERIAL_BAD_INPUT 1    /* non-finite strain or state, or a non-finite result */
#define PNC_MATERIAL_BAD_ARGUMENT 2 /* NULL material or array where one is required */
#define PNC_MATERIAL_INTERNAL 3     /* unexpected failure inside the library */
#define PNC_MATERIAL_UNKNOWN_NAME 4 /* a property or state name the material does not have */

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

/* ======================================================================================
 * ABI 1.1: the v2 point interface and the property queries (docs/plugin.md "ABI 1.1").
 * In the spirit of the MGIS behaviour data view: one extensible struct per call.
 * ====================================================================================== */

/* The minor ABI version the library was built with (PNC_MATERIAL_ABI_VERSION_MINOR). A host
 * that uses the functions below needs a library with minor >= 1; dlopen()-based hosts
 * should check it (pnc::fe_material::Plugin does, lazily, by symbol). */
PNC_MATERIAL_API int pnc_material_abi_version_minor(void);

/* tangent_request of pnc_material_point: which 6x6 tangent the call writes (Pa, row-major,
 * tangent[6*i + j] = d sigma_i / d eps_j, engineering shear strain, global frame). */
#define PNC_MATERIAL_TANGENT_NONE 0    /* no tangent; point.tangent may be NULL */
#define PNC_MATERIAL_TANGENT_ELASTIC 1 /* the undamaged stiffness [C0] (symmetric) */
#define PNC_MATERIAL_TANGENT_SECANT                                                                \
  2 /* [C0] + [C1(D)] of the END state: stress = K strain                                          \
       exactly; symmetric, no damage-growth term */
#define PNC_MATERIAL_TANGENT_CONSISTENT                                                            \
  3 /* d stress / d strain of the increment: the secant                                            \
       plus the damage-growth term of each loading mode                                            \
       (in general not symmetric); what                                                            \
       pnc_material_integrate() returns */

/* The version of the layout below; the layout only ever grows at the end. */
#define PNC_MATERIAL_POINT_VERSION 1

/* One integration point and increment: inputs, outputs and the error buffer of
 * pnc_material_integrate2(). The caller owns the struct and every array it points to; the
 * library keeps no pointer after the call returns. Arrays as in pnc_material_integrate():
 * Voigt 11, 22, 33, 23, 13, 12, engineering shear strain, stress in Pa.
 *
 * Set size = sizeof(pnc_material_point) and version = PNC_MATERIAL_POINT_VERSION (or call
 * pnc_material_point_init()). The library reads and writes only the first `size` bytes: a
 * smaller struct from an older header is accepted as long as it reaches `tangent` (its
 * missing trailing outputs are simply not written; without err/err_len there is no message);
 * a version newer than the library knows is refused (PNC_MATERIAL_BAD_ARGUMENT, with a
 * message when the struct reaches err_len: the layout is append-only). */
typedef struct pnc_material_point {
  uint32_t size;            /* bytes of this struct as the caller compiled it */
  uint32_t version;         /* PNC_MATERIAL_POINT_VERSION of the caller's header */
  double dt;                /* time increment, s: finite and >= 0; the law is rate-independent
                               and does not use it otherwise */
  int tangent_request;      /* PNC_MATERIAL_TANGENT_NONE / ELASTIC / SECANT / CONSISTENT */
  const double* state0;     /* state at the start, pnc_material_n_state() entries (in) */
  double* state1;           /* state at the end (out; may alias state0) */
  const double* strain0;    /* total strain at the start, 6 entries (in) */
  const double* dstrain;    /* strain increment, 6 entries (in) */
  double* stress;           /* Cauchy stress at the end, Pa, 6 entries (out) */
  double* tangent;          /* 36 entries, Pa (out); NULL only with TANGENT_NONE */
  double stored_energy;     /* out, J/m^3: the elastic energy density stored at the END of the
                               increment, 1/2 stress . strain (a state value, not an
                               increment; the NDM is a secant law) */
  double dissipated_energy; /* out, J/m^3: the energy density dissipated IN this increment,
                             psi(eps1, D0) - psi(eps1, D1): the stored energy released by the
                             increment's damage growth at the end strain (0 without growth).
                             Exact identity: stored1 - stored0 + dissipated =
                             1/2 (eps1 - eps0) . [S(D0)] (eps1 + eps0), the work of the
                             stress with the damage of the start state. The fitted law does
                             not guarantee it is >= 0 for every strain (docs/plugin.md). */
  char* err;                /* caller's buffer for one NUL-terminated message, or NULL */
  size_t err_len;           /* bytes of err (0 for none) */
} pnc_material_point;

/* Zeroes a point and sets size and version for this header. */
static inline void pnc_material_point_init(pnc_material_point* point) {
  size_t i;
  unsigned char* b = (unsigned char*)point;
  for (i = 0; i < sizeof *point; ++i)
    b[i] = 0;
  point->size = (uint32_t)sizeof *point;
  point->version = PNC_MATERIAL_POINT_VERSION;
}

/* Integrates the law over one increment described by *point. Returns PNC_MATERIAL_OK or:
 *  PNC_MATERIAL_BAD_ARGUMENT: NULL material or point, a size smaller than the fields up to
 *    `tangent`, an unknown (newer) version, an unknown tangent_request, a NULL array that is
 *    required (tangent is required unless TANGENT_NONE);
 *  PNC_MATERIAL_BAD_INPUT: a non-finite or negative dt, a non-finite strain or state, or a
 *    non-finite result (stress, state, tangent or energies);
 *  PNC_MATERIAL_INTERNAL: an unexpected failure.
 * On failure nothing but err is written. Never OK with a non-finite output. */
PNC_MATERIAL_API int pnc_material_integrate2(const pnc_material* m, pnc_material_point* point);

/* Scalar properties of the material, by name (units in docs/plugin.md and from
 * pnc_material_property_units()). All are of the undamaged law in the GLOBAL frame (the
 * platelet rotation applied), computed once, at the first query:
 *   elastic_stiffness_IJ   (I, J = 1..6) [C0], Pa, engineering Voigt
 *   damage_stiffness_K_IJ  (K = 1..n_damage_modes) d[C]/dD_K, Pa per unit damage
 *   n_damage_modes         3 (pnc) or 1 (pp)
 *   critical_stretch       lambda_c = (26/7)^(1/6), 1
 *   damage_onset_stretch   alpha * lambda_c: a mode damages once its stretch exceeds it, 1
 *   p_wave_modulus_max     the largest P-wave (longitudinal) modulus over all propagation
 *                          directions, max_n max eig of the acoustic tensor C_ijkl n_j n_l,
 *                          Pa; c = sqrt(p_wave_modulus_max / rho) bounds every wave speed
 *   youngs_modulus_I       (I = 1..3) 1 / S_II, S = [C0]^-1, Pa
 *   shear_modulus_23, _13, _12   1 / S_44, 1 / S_55, 1 / S_66, Pa
 *   poisson_ratio_IJ       (IJ = 12, 13, 23, 21, 31, 32) -S_IJ / S_II: lateral strain in J
 *                          per axial strain in I, 1
 * Unknown name or NULL: NaN with *status = PNC_MATERIAL_UNKNOWN_NAME (BAD_ARGUMENT for a NULL
 * material, INTERNAL if the properties cannot be computed); status may be NULL. */
PNC_MATERIAL_API double pnc_material_property(const pnc_material* m, const char* name, int* status);
/* Enumeration: the number of properties, the name and the units ("Pa", "1") of property i
 * (0-based); NULL outside. Strings live as long as the material. */
PNC_MATERIAL_API int pnc_material_n_properties(const pnc_material* m);
PNC_MATERIAL_API const char* pnc_material_property_name(const pnc_material* m, int i);
PNC_MATERIAL_API const char* pnc_material_property_units(const pnc_material* m, int i);

/* The undamaged stiffness [C0] (global frame, Pa, row-major, engineering Voigt) into C[36],
 * and d[C]/dD_mode (mode 0-based, < n_damage_modes; C1 is linear in D, so the secant
 * stiffness of a state is [C0] + sum_mode D_mode * d[C]/dD_mode). Return PNC_MATERIAL_OK or
 * PNC_MATERIAL_BAD_ARGUMENT (NULL, or mode out of range; nothing written). */
PNC_MATERIAL_API int pnc_material_elastic_stiffness(const pnc_material* m, double* C36);
PNC_MATERIAL_API int pnc_material_damage_stiffness(const pnc_material* m, int mode, double* C36);

/* 0-based index of a state variable by name (pnc_material_state_name()), or -1. So that one
 * loop over the damage modes k = 1..n_damage_modes serves both models, "kappaK" and "DK" are
 * accepted for every mode: for pp, "kappa1" and "D1" are its "kappa" and "D". */
PNC_MATERIAL_API int pnc_material_state_index(const pnc_material* m, const char* name);

/* The constants a model takes, without a material (for hosts that build one from a list of
 * named values, e.g. the JSON of `pnc card show --json`): their number (0 for an unknown
 * model) and names in the order pnc_material_create_from_constants() expects (NULL outside).
 * model is "pnc" or "pp"; static strings. */
PNC_MATERIAL_API int pnc_material_model_n_constants(const char* model);
PNC_MATERIAL_API const char* pnc_material_model_constant_name(const char* model, int i);

/* ======================================================================================
 * ABI 1.2: the batched entry (docs/plugin.md "ABI 1.2"). Many points of one material in one
 * call, in structure-of-arrays layout, in the spirit of MGIS's batch integration.
 * ====================================================================================== */

/* The version of the layout below; the layout only ever grows at the end. */
#define PNC_MATERIAL_POINT_SOA_VERSION 1

/* n points and one increment each: inputs, outputs and the error buffer of
 * pnc_material_integrate_batch(). The caller owns the struct and every array; the library
 * keeps no pointer after the call returns and allocates nothing per point.
 *
 * Layout: every array is a block of components, component k of point i at [k * ld + i]
 * (ld >= n, in doubles: a dense block has ld = n; a host may keep blocks for a larger
 * capacity and integrate the first n points). Units and Voigt order as in
 * pnc_material_integrate(): 11, 22, 33, 23, 13, 12, engineering shear strain, stress in Pa.
 *   strain0, dstrain  6 x ld (in)      total strain at the start and its increment
 *   state0            n_state x ld (in) state variable s of point i at [s * ld + i], in the
 *                                       order of pnc_material_state_name()
 *   state1            n_state x ld (out) the end state; may be the same block as state0
 *   stress            6 x ld (out), Pa
 *   tangent           36 x ld (out), Pa: ONE block in which entry (r, c) of the row-major
 *                     6x6 tangent of pnc_material_point (d sigma_r / d eps_c) is component
 *                     6 r + c: tangent[(6 r + c) * ld + i]. NULL only with TANGENT_NONE.
 *   stored_energy, dissipated_energy   n entries each (out, J/m^3, as in
 *                     pnc_material_point), or NULL when not wanted
 *   status            n entries (out): PNC_MATERIAL_OK or PNC_MATERIAL_BAD_INPUT per point,
 *                     or NULL
 * No two arrays may overlap, except state1 == state0 exactly.
 *
 * Set size = sizeof(pnc_material_point_soa) and version = PNC_MATERIAL_POINT_SOA_VERSION (or
 * call pnc_material_point_soa_init()). As for pnc_material_point, the library reads and writes
 * only the first `size` bytes: a smaller struct from an older header is accepted as long as it
 * reaches `tangent` (missing trailing fields are neither read nor written: no status array, no
 * energies, no message); a newer version is refused (PNC_MATERIAL_BAD_ARGUMENT). */
typedef struct pnc_material_point_soa {
  uint32_t size;             /* bytes of this struct as the caller compiled it */
  uint32_t version;          /* PNC_MATERIAL_POINT_SOA_VERSION of the caller's header */
  double dt;                 /* time increment of every point, s: finite and >= 0 (unused by
                                the rate-independent law otherwise) */
  int tangent_request;       /* PNC_MATERIAL_TANGENT_* for every point */
  size_t ld;                 /* leading dimension of every block, in doubles (>= n) */
  const double* strain0;     /* 6 x ld (in) */
  const double* dstrain;     /* 6 x ld (in) */
  const double* state0;      /* n_state x ld (in) */
  double* state1;            /* n_state x ld (out; may be state0) */
  double* stress;            /* 6 x ld (out), Pa */
  double* tangent;           /* 36 x ld (out), Pa; NULL only with TANGENT_NONE */
  int* status;               /* n (out) or NULL */
  double* stored_energy;     /* n (out, J/m^3) or NULL */
  double* dissipated_energy; /* n (out, J/m^3) or NULL */
  size_t n_failed;           /* out: how many points failed */
  size_t first_failed;       /* out: index of the first failed point (n when none) */
  char* err;                 /* caller's buffer for one NUL-terminated message, or NULL */
  size_t err_len;            /* bytes of err (0 for none) */
} pnc_material_point_soa;

/* Zeroes a batch view and sets size and version for this header. */
static inline void pnc_material_point_soa_init(pnc_material_point_soa* batch) {
  size_t i;
  unsigned char* b = (unsigned char*)batch;
  for (i = 0; i < sizeof *batch; ++i)
    b[i] = 0;
  batch->size = (uint32_t)sizeof *batch;
  batch->version = PNC_MATERIAL_POINT_SOA_VERSION;
}

/* Integrates the law over one increment at each of the n points of *batch: for every point
 * the numbers pnc_material_integrate2() gives for the same arrays and tangent_request (stress,
 * state and tangent bit for bit; energies to the last bits, docs/plugin.md), and the same
 * points fail. n = 0 is allowed (the arrays may then be NULL).
 * Returns PNC_MATERIAL_OK when every point succeeded, or:
 *  PNC_MATERIAL_BAD_ARGUMENT: NULL material or batch, a size smaller than the fields up to
 *    `tangent`, an unknown version or tangent_request, ld < n, a NULL array that is required;
 *    nothing but err is written;
 *  PNC_MATERIAL_BAD_INPUT: a non-finite or negative dt (nothing but err is written), or one or
 *    more points failed (a non-finite strain or state, or a non-finite result). A failed point
 *    gets status PNC_MATERIAL_BAD_INPUT and nothing else written; every other point is computed
 *    and written. n_failed counts them, first_failed is the first, and err names it (index,
 *    field, value, rule);
 *  PNC_MATERIAL_INTERNAL: an unexpected failure (outputs unspecified).
 * Thread safety as for pnc_material_integrate2(): many batches of one material may run at
 * once (on disjoint arrays). */
PNC_MATERIAL_API int pnc_material_integrate_batch(const pnc_material* m, size_t n,
                                                  pnc_material_point_soa* batch);

/* ======================================================================================
 * ABI 1.3: the damage law's stretches and damage as queries (docs/plugin.md "ABI 1.3").
 * ====================================================================================== */

/* The damage D of damage mode `mode` (0-based, < n_damage_modes) at the largest mode stretch
 * kappa reached (the state variable "kappaK", K = mode + 1; dimensionless, a stretch), as
 * pnc_material_integrate2() computes it: 0 up to damage_onset_stretch, the law's D(kappa)
 * beyond. *D (dimensionless) is written; dD_dkappa, if not NULL, receives dD/dkappa (per unit
 * stretch). So that a host (a regularisation, a fracture closure) needs no zero-strain
 * integration calls to learn the law. Return PNC_MATERIAL_OK, or PNC_MATERIAL_BAD_ARGUMENT (a
 * NULL material or D, mode out of range, kappa not finite or negative; nothing written). */
PNC_MATERIAL_API int pnc_material_damage_of_stretch(const pnc_material* m, int mode, double kappa,
                                                    double* D, double* dD_dkappa);

/* The mode stretches of a strain: lambda[k] (k < n_damage_modes; dimensionless) is what
 * pnc_material_integrate2() compares with the state's kappa(k+1) at the end strain `strain` (6,
 * engineering Voigt, GLOBAL frame, as the strain arrays of the integration), the same number
 * bit for bit (one platelet-frame strain and one stretch routine, D351); dlambda (if not
 * NULL) receives d lambda_k / d strain_j at [6 k + j] (global frame). A host that regularises
 * the damage driving stretch (a nonlocal average, its tangent) needs no probing integrations.
 * Return PNC_MATERIAL_OK, or PNC_MATERIAL_BAD_ARGUMENT (a NULL material, strain or lambda; a
 * strain that is not finite; nothing written). */
PNC_MATERIAL_API int pnc_material_mode_stretch(const pnc_material* m, const double* strain,
                                               double* lambda, double* dlambda);

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
/* ABI 1.1 */
typedef int (*pnc_material_abi_version_minor_fn)(void);
typedef int (*pnc_material_integrate2_fn)(const pnc_material*, pnc_material_point*);
typedef double (*pnc_material_property_fn)(const pnc_material*, const char*, int*);
typedef int (*pnc_material_n_properties_fn)(const pnc_material*);
typedef const char* (*pnc_material_property_name_fn)(const pnc_material*, int);
typedef const char* (*pnc_material_property_units_fn)(const pnc_material*, int);
typedef int (*pnc_material_elastic_stiffness_fn)(const pnc_material*, double*);
typedef int (*pnc_material_damage_stiffness_fn)(const pnc_material*, int, double*);
typedef int (*pnc_material_state_index_fn)(const pnc_material*, const char*);
typedef int (*pnc_material_model_n_constants_fn)(const char*);
typedef const char* (*pnc_material_model_constant_name_fn)(const char*, int);
/* ABI 1.2 */
typedef int (*pnc_material_integrate_batch_fn)(const pnc_material*, size_t,
                                               pnc_material_point_soa*);
/* ABI 1.3 */
typedef int (*pnc_material_damage_of_stretch_fn)(const pnc_material*, int, double, double*,
                                                 double*);
typedef int (*pnc_material_mode_stretch_fn)(const pnc_material*, const double*, double*, double*);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* PNC_FE_MATERIAL_PNC_MATERIAL_H */
