// Cell sort of the particles of the uGIMP solver (solver.hpp, Solver::sort_particles, D354)
// and the huge-page advice of its arrays (D430). The sort:
// a stable counting sort on the grid cell of each centroid, so that particles sharing stencil
// nodes sit next to each other in memory. SI units (positions m).
#include "pnc/gimp_coupler/solver.hpp"

#include "pnc/core/huge_pages.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace pnc::gimp {

namespace {
/// a <- a[perm] (new position q holds the old element perm[q]).
template <class T> void permute(std::vector<T>& a, const std::vector<std::size_t>& perm) {
  std::vector<T> tmp(a.size());
  for (std::size_t q = 0; q < perm.size(); ++q)
    tmp[q] = a[perm[q]];
  a.swap(tmp);
}

/// Blocks of `stride` values, one per particle: block q <- old block perm[q]. A vector whose
/// size is not n * stride (not allocated yet) is left alone.
void permute_blocks(std::vector<double>& a, const std::vector<std::size_t>& perm,
                    std::size_t stride) {
  if (stride == 0 || a.size() != perm.size() * stride) return;
  std::vector<double> tmp(a.size());
  for (std::size_t q = 0; q < perm.size(); ++q)
    std::copy_n(a.data() + perm[q] * stride, stride, tmp.data() + q * stride);
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
  permute_blocks(P.state, perm, static_cast<std::size_t>(P.state_stride));
  // The next P2G recomputes these for every particle; permuted anyway so that nothing read
  // between steps sees another particle's weights or crack fields.
  if (wval_.size() == n) permute(wval_, perm);
  if (wder_.size() == n) permute(wder_, perm);
  permute_blocks(law_scratch_, perm, law_scratch_stride_); // the laws' scratch (D416)
  if (fmask_.size() == n) permute(fmask_, perm);
  std::vector<std::size_t> where(n); // old index -> new index
  for (std::size_t q = 0; q < n; ++q)
    where[perm[q]] = q;
  for (auto& tr : tractions)
    for (auto& p : tr.particles)
      p = where[p];
  advise_huge_pages(); // the permuted arrays are new allocations
}

// D430: every array a step streams, once it has its size, when together they exceed what the
// caches hold (16 MiB; below, no page walk to save and up to 2 MiB of memory per array to lose);
// arrays under 64 KiB are skipped by prefer_huge_pages itself. Advice only: the data do not
// change.
template <int D> void Solver<D>::advise_huge_pages() const {
  constexpr std::size_t kMinTotal = std::size_t{16} << 20;
  std::vector<std::pair<const void*, std::size_t>> spans;
  const auto add = [&](const auto& v) { spans.push_back({v.data(), v.size() * sizeof(v[0])}); };
  const auto& P = particles;
  for (const auto* v : {&P.x, &P.x0, &P.v, &P.l, &P.fext, &gp_, &gfi_, &gfe_, &gfi0_, &gvs_, &gvn_})
    add(*v);
  for (const auto* v : {&P.m, &P.V0, &P.V, &P.W, &P.state, &gm_, &law_scratch_})
    add(*v);
  add(P.F);
  add(P.sigma);
  add(P.mat);
  add(wval_);
  add(wder_);
  for (const auto& b : buf_) {
    add(b.m);
    add(b.p);
    add(b.fi);
    add(b.fe);
  }
  std::size_t total = 0;
  for (const auto& s : spans)
    total += s.second;
  if (total < kMinTotal) return;
  for (const auto& s : spans)
    prefer_huge_pages(s.first, s.second);
}

template void Solver<2>::sort_particles();
template void Solver<3>::sort_particles();
template void Solver<2>::advise_huge_pages() const;
template void Solver<3>::advise_huge_pages() const;

} // namespace pnc::gimp
