// Cell sort of the particles of the uGIMP solver (solver.hpp, Solver::sort_particles, D354):
// a stable counting sort on the grid cell of each centroid, so that particles sharing stencil
// nodes sit next to each other in memory. SI units (positions m).
#include "pnc/gimp_coupler/solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace pnc::gimp {

namespace {
/// a <- a[perm] (new position q holds the old element perm[q]).
template <class T> void permute(std::vector<T>& a, const std::vector<std::size_t>& perm) {
  std::vector<T> tmp(a.size());
  for (std::size_t q = 0; q < perm.size(); ++q)
    tmp[q] = a[perm[q]];
  a.swap(tmp);
}
} // namespace

template <int D> void Solver<D>::sort_particles() {
  auto& P = particles;
  const std::size_t n = P.size();
  if (n == 0) return;
  // Cell of the centroid per axis, clamped to the grid's cells (a particle outside is caught
  // by the next P2G with its own message).
  std::int64_t ncell = 1;
  for (int a = 0; a < D; ++a)
    ncell *= std::max(1, grid.n[a] - 1);
  std::vector<std::int64_t> cell(n);
  for (std::size_t p = 0; p < n; ++p) {
    std::int64_t id = 0;
    for (int a = D - 1; a >= 0; --a) {
      const int nc = std::max(1, grid.n[a] - 1);
      const double s = std::floor((P.x[p][a] - grid.origin[a]) / grid.h);
      const int c = s >= 0.0 ? static_cast<int>(std::min<double>(s, nc - 1)) : 0;
      id = id * nc + c;
    }
    cell[p] = id;
  }
  // Stable counting sort: perm[q] = the old index of the particle now at q.
  std::vector<std::size_t> start(static_cast<std::size_t>(ncell) + 1, 0);
  for (std::size_t p = 0; p < n; ++p)
    ++start[static_cast<std::size_t>(cell[p]) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::size_t> perm(n);
  for (std::size_t p = 0; p < n; ++p)
    perm[start[static_cast<std::size_t>(cell[p])]++] = p;
  bool identity = true;
  for (std::size_t q = 0; q < n && identity; ++q)
    identity = perm[q] == q;
  if (identity) return;

  permute(P.x, perm);
  permute(P.x0, perm);
  permute(P.v, perm);
  permute(P.l, perm);
  permute(P.fext, perm);
  permute(P.m, perm);
  permute(P.V0, perm);
  permute(P.V, perm);
  permute(P.F, perm);
  permute(P.sigma, perm);
  permute(P.W, perm);
  permute(P.mat, perm);
  if (order_.size() == n) permute(order_, perm);
  const auto stride = static_cast<std::size_t>(P.state_stride);
  if (stride > 0) {
    std::vector<double> tmp(P.state.size());
    for (std::size_t q = 0; q < n; ++q)
      std::copy_n(P.state.data() + perm[q] * stride, stride, tmp.data() + q * stride);
    P.state.swap(tmp);
  }
  // The next P2G recomputes these for every particle; permuted anyway so that nothing read
  // between steps sees another particle's weights or crack fields.
  if (wcache_.size() == n) permute(wcache_, perm);
  const std::size_t ls = law_scratch_stride_; // the laws' scratch (D416) follows its particle
  if (ls > 0 && law_scratch_.size() == n * ls) {
    std::vector<double> tmp(law_scratch_.size());
    for (std::size_t q = 0; q < n; ++q)
      std::copy_n(law_scratch_.data() + perm[q] * ls, ls, tmp.data() + q * ls);
    law_scratch_.swap(tmp);
  }
  if (fmask_.size() == n) permute(fmask_, perm);
  std::vector<std::size_t> where(n); // old index -> new index
  for (std::size_t q = 0; q < n; ++q)
    where[perm[q]] = q;
  for (auto& tr : tractions)
    for (auto& p : tr.particles)
      p = where[p];
}

template void Solver<2>::sort_particles();
template void Solver<3>::sort_particles();

} // namespace pnc::gimp
