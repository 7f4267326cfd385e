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
/// An empty vector with room for n elements; when `huge`, its memory is advised as huge pages
/// before it is first written, so that it is backed by them from its first touch (D430).
template <class T> std::vector<T> fresh(std::size_t n, bool huge) {
  std::vector<T> v;
  v.reserve(n);
  if (huge) prefer_huge_pages(v.data(), n * sizeof(T));
  return v;
}

/// a <- a[perm] (new position q holds the old element perm[q]).
template <class T>
void permute(std::vector<T>& a, const std::vector<std::size_t>& perm, bool huge) {
  std::vector<T> tmp = fresh<T>(a.size(), huge);
  for (std::size_t q = 0; q < perm.size(); ++q)
    tmp.push_back(a[perm[q]]);
  a.swap(tmp);
}

/// Blocks of `stride` values, one per particle: block q <- old block perm[q]. A vector whose
/// size is not n * stride (not allocated yet) is left alone.
void permute_blocks(std::vector<double>& a, const std::vector<std::size_t>& perm,
                    std::size_t stride, bool huge) {
  if (stride == 0 || a.size() != perm.size() * stride) return;
  std::vector<double> tmp = fresh<double>(a.size(), huge);
  for (std::size_t q = 0; q < perm.size(); ++q)
    tmp.insert(tmp.end(), a.data() + perm[q] * stride, a.data() + (perm[q] + 1) * stride);
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
  const bool huge = huge_pages_wanted(); // the new arrays in huge pages from the start (D430)

  const auto each = [&](auto&... a) { (permute(a, perm, huge), ...); };
  each(P.x, P.x0, P.v, P.l, P.fext, P.m, P.V0, P.V, P.F, P.sigma, P.W, P.mat);
  if (order_.size() == n) permute(order_, perm, huge);
  permute_blocks(P.state, perm, static_cast<std::size_t>(P.state_stride), huge);
  // The next P2G recomputes these for every particle; permuted anyway so that nothing read
  // between steps sees another particle's weights or crack fields.
  if (wval_.size() == n) permute(wval_, perm, huge);
  if (wder_.size() == n) permute(wder_, perm, huge);
  permute_blocks(law_scratch_, perm, law_scratch_stride_, huge); // the laws' scratch (D416)
  if (fmask_.size() == n) permute(fmask_, perm, huge);
  std::vector<std::size_t> where(n); // old index -> new index
  for (std::size_t q = 0; q < n; ++q)
    where[perm[q]] = q;
  for (auto& tr : tractions)
    for (auto& p : tr.particles)
      p = where[p];
  advise_huge_pages(); // (what the advice before the first write did not get)
}

// D430: every array a step streams, once it has its size, when together they exceed what the
// caches hold (16 MiB; below, no page walk to save and up to 2 MiB of memory per array to lose);
// arrays under 64 KiB are skipped by prefer_huge_pages itself. Advice only: the data do not
// change.
template <int D> std::vector<std::pair<const void*, std::size_t>> Solver<D>::array_spans() const {
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
  return spans;
}

namespace {
bool spans_want_huge_pages(const std::vector<std::pair<const void*, std::size_t>>& spans) {
  constexpr std::size_t kMinTotal = std::size_t{16} << 20;
  std::size_t total = 0;
  for (const auto& s : spans)
    total += s.second;
  return total >= kMinTotal && huge_pages_enabled();
}
} // namespace

template <int D> bool Solver<D>::huge_pages_wanted() const {
  return spans_want_huge_pages(array_spans());
}

template <int D> void Solver<D>::advise_huge_pages() const {
  const auto spans = array_spans(); // listed once for the rule and the advice
  if (!spans_want_huge_pages(spans)) return;
  for (const auto& s : spans)
    prefer_huge_pages(s.first, s.second);
}

template void Solver<2>::sort_particles();
template void Solver<3>::sort_particles();
template void Solver<2>::advise_huge_pages() const;
template void Solver<3>::advise_huge_pages() const;
template bool Solver<2>::huge_pages_wanted() const;
template bool Solver<3>::huge_pages_wanted() const;
template std::vector<std::pair<const void*, std::size_t>> Solver<2>::array_spans() const;
template std::vector<std::pair<const void*, std::size_t>> Solver<3>::array_spans() const;

} // namespace pnc::gimp
