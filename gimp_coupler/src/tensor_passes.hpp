#pragma once
// The per-particle grid transfers of one uGIMP step by rows of the tensor-product stencil
// (D404), for particles that use field 0 at every node of their support (no crack field,
// fmask = 0); solver_step.cpp calls them, tensor_passes.cpp compiles them twice (baseline and
// AVX2, chosen at run time as the weights are, D377).
//
// The stencil of a particle is 3^(D-1) rows of three nodes along axis 0, each row's nodes
// consecutive in the node arrays, so a row of a node vector field is 3 D consecutive doubles
// ("lanes" q = D i + a: node i of the row, component a). With r the product of the other
// axes' weights for the row and rd[b] that product with axis b + 1's weight replaced by its
// derivative,
//   S_n = w0_i r,   grad S_n = (d0_i r, w0_i rd[0], w0_i rd[1]).
// Scatters add r x (a per-particle lane pattern) to each row; gathers sum r x (a row's lanes)
// and multiply by the lane pattern once at the end. Every lane is its own sum, so the lane
// loops vectorise without reordering a sum, and both compiled copies give the same bits.
// Against the node-by-node forms (assemble_stencil, then one contraction per node) the
// products are grouped differently: equal to round-off, not bit for bit (the tests in
// tests/gimp_coupler/test_tensor_passes.cpp bound the difference by the terms' magnitudes).
// Units as in solver.hpp: S dimensionless, grad S 1/m, node arrays in SI.
#include "pnc/gimp_coupler/weights.hpp"

#include <cstdint>

namespace pnc::gimp::detail {

/// The inputs of one particle's P2G, read where they are stored (the particle arrays), not
/// copied: a packed copy written just before the call and read as vectors stalls on store
/// forwarding.
template <int D> struct P2GParticle {
  double m;            ///< mass, kg
  double V;            ///< volume, m^3
  const double* v;     ///< D velocity components, m/s
  const double* sigma; ///< 3 x 3 Cauchy stress, column-major (Mat3), Pa
  const double* fext;  ///< D external force components, N (read when the call asks for it)
};

/// Node arrays of one grid copy, each node vector as D consecutive doubles (Eigen's fixed
/// D-vectors in a std::vector); fe may be null when no external force is scattered.
struct NodeArrays {
  double* m;  ///< mass, kg (one double per node)
  double* p;  ///< momentum, kg m/s
  double* fi; ///< internal force, N
  double* fe; ///< external force, N
};

/// The row kernels of one compiled copy (see row_kernels()).
template <int D> struct RowKernels {
  /// P2G of one particle: m += S m_p, p += S (m v)_p, fi -= (sigma V) grad S (row a of sigma:
  /// force component a), and with `external` fe += S fext. The weights as the solver caches
  /// them, values and derivatives apart (D422).
  void (*scatter)(const Grid<D>& g, const AxisValues<D>& av, const AxisSlopes<D>& ad,
                  const P2GParticle<D>& in, bool external, const NodeArrays& out);
  /// fi -= (sigma V) grad S over the stencil (N; sigma as in P2GParticle, Pa; V in m^3).
  void (*scatter_force)(const Grid<D>& g, const AxisValues<D>& av, const AxisSlopes<D>& ad,
                        const double* sigma, double V, double* fi);
  /// grad[a][c] = sum_n v_n[a] (grad S_n)_c (v in m/s: 1/s).
  void (*gradient)(const Grid<D>& g, const AxisValues<D>& av, const AxisSlopes<D>& ad,
                   const double* v, double (&grad)[D][D]);
  /// G2P sums: vs_p[a] = sum_n S_n vs_n[a], dv_p[a] = sum_n S_n (vn_n[a] - v0_n[a]) (m/s);
  /// the values of the weights only.
  void (*velocities)(const Grid<D>& g, const AxisValues<D>& av, const double* vs, const double* vn,
                     const double* v0, double (&vs_p)[D], double (&dv_p)[D]);
};

/// The copy for this CPU: AVX-512 where pnc::cpu_has_avx512(), else AVX2 where
/// pnc::cpu_has_avx2(), else the baseline build (D377, D414).
template <int D> const RowKernels<D>& row_kernels();
/// Each copy, for the tests: 0 = baseline, 1 = AVX2, 2 = AVX-512 (the baseline again where the
/// build has no vector copies, PNC_HAVE_AVX2_COPY = 0).
template <int D> const RowKernels<D>& row_kernels(int copy);

} // namespace pnc::gimp::detail
