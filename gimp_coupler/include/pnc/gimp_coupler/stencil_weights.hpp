#pragma once
// pnc/gimp_coupler/stencil_weights.hpp: the node indices and weights S of a particle's 3^D
// stencil without the gradients, for the passes that use S only (G2P, the contact
// displacements; D378). The same loop as assemble_stencil (assemble_stencil_parts in
// weights.hpp), so node and S equal its output bit for bit. Units: S dimensionless.
#include "pnc/gimp_coupler/weights.hpp"

namespace pnc::gimp {

/// st.node and st.S of the stencil of `aw` (st.dS is left as it was; `aw`: AxisWeights<D>, or
/// AxisValues<D> since the derivatives are not read).
template <int D, template <int> class AW>
inline void assemble_stencil_weights(const Grid<D>& g, const AW<D>& aw, Stencil<D>& st) {
  assemble_stencil_parts<false>(g, aw, st);
}

} // namespace pnc::gimp
