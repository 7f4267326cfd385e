#pragma once
// pnc/gimp_coupler/stencil_weights.hpp: the node indices and weights S of a particle's 3^D
// stencil without the gradients, for the passes that use S only (G2P, the contact
// displacements; D378). The same products in the same order as assemble_stencil
// (weights.hpp), so node and S equal its output bit for bit. Units: S dimensionless.
#include "pnc/gimp_coupler/weights.hpp"

#include <cstdint>

namespace pnc::gimp {

/// st.node and st.S of the stencil of `aw` (st.dS is left as it was).
template <int D>
inline void assemble_stencil_weights(const Grid<D>& g, const AxisWeights<D>& aw, Stencil<D>& st) {
  const auto& w = aw.w;
  if constexpr (D == 2) {
    int c = 0;
    for (int j = 0; j < 3; ++j) {
      const std::int64_t row = static_cast<std::int64_t>(aw.i0[1] + j) * g.n[0] + aw.i0[0];
      for (int i = 0; i < 3; ++i, ++c) {
        st.node[c] = row + i;
        st.S[c] = w[0][i] * w[1][j];
      }
    }
  } else {
    int c = 0;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) {
        const std::int64_t row =
            (static_cast<std::int64_t>(aw.i0[2] + k) * g.n[1] + (aw.i0[1] + j)) * g.n[0] + aw.i0[0];
        const double wjk = w[1][j] * w[2][k];
        for (int i = 0; i < 3; ++i, ++c) {
          st.node[c] = row + i;
          st.S[c] = w[0][i] * wjk;
        }
      }
  }
}

} // namespace pnc::gimp
