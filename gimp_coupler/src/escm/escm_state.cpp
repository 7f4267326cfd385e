// Checkpoint and restore of the ESCM coupler (escm.hpp Coupler::checkpoint/restore; docs/escm.md
// "Checkpoint and resume").
#include "coupler_impl.hpp"

#include "pnc/md/atoms.hpp"

#include <stdexcept>

namespace pnc::gimp::escm {

// Per-atom arrays by id - 1 straight from the local arrays (md/atoms.hpp: one MPI rank;
// LAMMPS's own scatter goes through the atom map, which can name a ghost copy).
std::vector<double> Coupler::Impl::gather(const char* name, int count) const {
  return md::gather_local(lmp->handle(), name, count);
}

void Coupler::Impl::scatter(const char* name, const std::vector<double>& v) const {
  md::scatter_local(lmp->handle(), name, v);
}

// Puts atoms into LAMMPS and makes a restart point: x, v, image; new Langevin fixes
// (segment); `run 0` (box, neighbour lists, ghosts rebuilt from x; its forces are discarded);
// the saved forces back.
void Coupler::Impl::apply_atoms(const std::vector<double>& x, const std::vector<double>& v,
                                const std::vector<double>& f, const std::vector<double>& image) {
  scatter("x", x);
  scatter("v", v);
  scatter("image", image);
  langevin_fixes();
  block_start = static_cast<long>(lmp->thermo("step"));
  cmd("run 0 post no");
  scatter("f", f);
}

CouplerState Coupler::Impl::save() const {
  CouplerState st;
  for (int k : ivc_cells) {
    const Cell& c = cells[static_cast<std::size_t>(k)];
    st.mean_A.push_back(c.mean_A);
    st.prev_mean_A.push_back(c.prev_mean_A);
    st.velocity_mps.push_back(c.velocity_mps);
    st.force_N.push_back(c.force_N);
    st.atom_force.push_back(c.atom_force);
  }
  st.log = log;
  st.acc = acc;
  st.pe0 = pe0;
  st.heat_offset_int = heat_off_int;
  st.heat_offset_ivc = heat_off_ivc;
  st.prescribed_work = solver.prescribed_work;
  st.segment = segment;
  st.md_step = static_cast<long>(lmp->thermo("step"));
  st.timing = timing;
  st.x = gather("x", 3);
  st.v = gather("v", 3);
  st.f = gather("f", 3);
  const auto im = gather("image", 3), ty = gather("type", 1);
  st.image.assign(im.begin(), im.end());
  st.type.assign(ty.begin(), ty.end());
  return st;
}

CouplerState Coupler::Impl::checkpoint() {
  if (!ready) throw std::runtime_error("escm: checkpoint() before setup()");
  const auto x = gather("x", 3), v = gather("v", 3), f = gather("f", 3), im = gather("image", 3);
  ++segment;
  heat_off_int = acc.heat_removed_int;
  heat_off_ivc = acc.heat_removed_ivc;
  apply_atoms(x, v, f, im);
  return save();
}

void Coupler::Impl::restore(const CouplerState& st) {
  if (!ready) throw std::runtime_error("escm: restore() before setup()");
  const std::size_t n3 = 3 * static_cast<std::size_t>(natoms);
  auto bad_size = [](const std::string& what, std::size_t got, std::size_t want) {
    throw std::runtime_error("escm: restore: " + what + " has " + std::to_string(got) +
                             " entries, this set-up needs " + std::to_string(want));
  };
  if (st.x.size() != n3) bad_size("x", st.x.size(), n3);
  if (st.v.size() != n3) bad_size("v", st.v.size(), n3);
  if (st.f.size() != n3) bad_size("f", st.f.size(), n3);
  if (st.image.size() != n3) bad_size("image", st.image.size(), n3);
  if (st.mean_A.size() != ivc_cells.size())
    bad_size("IVC cells", st.mean_A.size(), ivc_cells.size());
  if (st.prev_mean_A.size() != ivc_cells.size() || st.velocity_mps.size() != ivc_cells.size() ||
      st.force_N.size() != ivc_cells.size() || st.atom_force.size() != ivc_cells.size())
    bad_size("IVC cell arrays", st.prev_mean_A.size(), ivc_cells.size());
  if (!st.type.empty()) {
    const auto ty = gather("type", 1);
    for (std::size_t i = 0; i < ty.size() && i < st.type.size(); ++i)
      if (static_cast<int>(ty[i]) != st.type[i])
        throw std::runtime_error("escm: restore: atom " + std::to_string(i + 1) + " has type " +
                                 std::to_string(st.type[i]) + " in the checkpoint, " +
                                 std::to_string(static_cast<int>(ty[i])) + " in this set-up");
  }
  for (std::size_t k = 0; k < ivc_cells.size(); ++k) {
    Cell& c = cells[static_cast<std::size_t>(ivc_cells[k])];
    c.mean_A = st.mean_A[k];
    c.prev_mean_A = st.prev_mean_A[k];
    c.velocity_mps = st.velocity_mps[k];
    c.force_N = st.force_N[k];
    c.atom_force = st.atom_force[k];
    fx[k] = c.atom_force[0];
    fy[k] = c.atom_force[1];
  }
  log = st.log;
  acc = st.acc;
  pe0 = st.pe0;
  heat_off_int = st.heat_offset_int;
  heat_off_ivc = st.heat_offset_ivc;
  solver.prescribed_work = st.prescribed_work;
  segment = st.segment;
  timing = st.timing;
  apply_atoms(st.x, st.v, st.f, std::vector<double>(st.image.begin(), st.image.end()));
}

} // namespace pnc::gimp::escm
