#pragma once
// The scratch of one chunk of the batched NDM route (ndm_batch.cpp, decisions D260, D261,
// D399) and the small branch-free helpers its passes share. Internal to the damage library:
// included by ndm_batch.cpp only (its passes are inlined into one function per instruction
// set, D386).
#include "ndm_internal.hpp"

#include <cstddef>

namespace pnc::damage::batch {

constexpr std::size_t kChunk = 32;
// Chunk::path. kKernel: damage growth (a loading mode whose damage grows); the point takes the
// vectorised damage-growth pass (D399, D403; pp points too, D419), which may hand it back to
// integrate_row_major() (Chunk::vec_growth).
constexpr double kElastic = 0.0, kUnloading = 1.0, kKernel = 2.0;

// Scratch of one chunk (about 34 KB on the stack; no allocation).
struct Chunk {
  double eps[6][kChunk]; // global strain at the end
  double el[6][kChunk];  // platelet-frame strain (a copy of eps without rotation)
  double s0[6][kChunk];  // state at the start (flat layout)
  double lam[3][kChunk]; // mode stretches
  double kap[3][kChunk]; // kappa at the end
  double D[3][kChunk];   // damage at the end
  double sig[6][kChunk]; // stress at the end
  // Secant stiffness (row-major entry rc) of the unloading points, compact (entry j of uidx),
  // formed once for their stress and then written as their tangent.
  double Ku[36][kChunk];
  double stored[kChunk]; // energies
  double diss[kChunk];
  double bad[kChunk]; // 0 for a point whose inputs and results are finite (sum of x * 0)
  // Path (kElastic, kUnloading, kKernel) as a double: the loops that set it then hold one
  // element type, which the vectoriser needs.
  double path[kChunk];
  // Set by the growth pass for its points only: integrated there (1) or handed back to the
  // kernel (0: a capped mode grows at a repeated lambda_max; D399, D403). The pieces the pass
  // takes from the stretch pass (compute_stretch()'s Stretch): lambda_max, the shear t_k of each
  // mode (|g12| / 2 of modes 1 and 2 and 0 of mode 3 for a block-diagonal strain),
  // d lambda_k / d t_k and whether the mode's cap binds (1) or not (0).
  double vec_growth[kChunk];
  double lmax[kChunk];
  double tsh[3][kChunk];
  double grow[3][kChunk];
  double clip[3][kChunk];
  double dg[3][kChunk]; // dD/dx of a loading mode (its damage growth), else 0
  // Consistent tangent of the damage-growth points of the vectorised pass, compact (D399). (The
  // pass's arrays come last: the layout of the others is the one measured before it.)
  double Kg[36][kChunk];
};

// Which points of a chunk have a plane strain (detail::is_plane of the global strain): all,
// none or some. The products with the strain then take row_plane(), row_full() or
// times_row()'s selection of the two, chosen once per chunk: every point gets the numbers
// times_row() gives it (D401).
enum class Planes { all, none, mixed };

template <Planes P, class Row>
[[gnu::always_inline]] inline double times_row_as(const Row& a, double e0, double e1, double e2,
                                                  double e3, double e4, double e5) {
  if constexpr (P == Planes::all)
    return detail::row_plane(a, e0, e1, e5);
  else if constexpr (P == Planes::none)
    return detail::row_full(a, e0, e1, e2, e3, e4, e5);
  else
    return detail::times_row(a, e0, e1, e2, e3, e4, e5);
}

// The count u (1 <= u <= kChunk) of a compact block rounded up to whole vectors of 4 doubles:
// the passes over a compact block run their loops over padded(u) lanes, the lanes past u
// repeating the last point, so that no point takes the loops' scalar remainder (a block holds a
// few points: about 6 growth and 3 unloading points of a chunk in bench_batch's mixes; D401).
constexpr std::size_t kLanes = 4;
static_assert(kChunk % kLanes == 0, "a padded block must fit in a chunk");
[[gnu::always_inline]] inline std::size_t padded(std::size_t u) {
  return (u + kLanes - 1) / kLanes * kLanes;
}

// x * 0 is 0 for finite x and NaN otherwise: a branch-free finiteness accumulator.
[[gnu::always_inline]] inline double nf(double x) {
  return x * 0.0;
}

// a . b of two 6-vectors in the order of Eigen's 6-vector dot with SSE2 packets (the kernel is
// compiled for the baseline): pairs (0, 1), (2, 3), (4, 5), reduced as p0 + (p1 + p2), then
// lane 0 + lane 1.
template <class A, class B> [[gnu::always_inline]] inline double dot6(const A& a, const B& b) {
  const double l0 = a[0] * b[0] + (a[2] * b[2] + a[4] * b[4]);
  const double l1 = a[1] * b[1] + (a[3] * b[3] + a[5] * b[5]);
  return l0 + l1;
}

// 0.5 sigma . eps of point i as the kernel forms it (0.5 * sigma.dot(eps)).
[[gnu::always_inline]] inline double half_dot(const double (&s)[6][kChunk],
                                              const double (&e)[6][kChunk], std::size_t i) {
  const double l0 = s[0][i] * e[0][i] + (s[2][i] * e[2][i] + s[4][i] * e[4][i]);
  const double l1 = s[1][i] * e[1][i] + (s[3][i] * e[3][i] + s[5][i] * e[5][i]);
  return 0.5 * (l0 + l1);
}

} // namespace pnc::damage::batch
