// Coarse-grained polypropylene force field -> LAMMPS commands (units real).
#include "pnc/md/forcefield.hpp"

#include "pnc/core/error.hpp"

#include <fmt/format.h>

#include <cmath>

namespace pnc::md {

std::array<double, 5> PolymerForceField::lammps_dihedral_A() const {
  // cos(omega) = -cos(phi): C_n cos^n(omega) = C_n (-1)^n cos^n(phi) = A_(n+1) cos^n(phi).
  return {C[0], -C[1], C[2], -C[3], 0.0};
}

void PolymerForceField::validate(const std::string& source) const {
  auto pos = [&](const char* name, double v) {
    if (!(v > 0.0) || !std::isfinite(v))
      fail(source, name, fmt::format("{}", v), "must be a finite number > 0");
  };
  pos("forcefield.bead_mass", bead_mass);
  pos("forcefield.k_l", k_l);
  pos("forcefield.l0", l0);
  pos("forcefield.k_theta", k_theta);
  pos("forcefield.epsilon", epsilon);
  pos("forcefield.sigma", sigma);
  if (!(theta0_deg > 0.0 && theta0_deg < 180.0))
    fail(source, "forcefield.theta0_deg", fmt::format("{}", theta0_deg), "must be in (0, 180)");
  if (!(cutoff_sigma >= 1.2 && cutoff_sigma <= 5.0))
    fail(source, "forcefield.cutoff_sigma", fmt::format("{}", cutoff_sigma), "must be in [1.2, 5]");
  for (std::size_t n = 0; n < 4; ++n)
    if (!std::isfinite(C[n]))
      fail(source, fmt::format("forcefield.C[{}]", n), fmt::format("{}", C[n]), "must be finite");
}

std::vector<std::string> polymer_forcefield_commands(const PolymerForceField& ff) {
  const auto A = ff.lammps_dihedral_A();
  return {
      fmt::format("pair_style lj/cut {:.10g}", ff.cutoff()),
      fmt::format("pair_coeff * * {:.12g} {:.12g}", ff.epsilon, ff.sigma),
      "pair_modify shift no tail no",
      "bond_style harmonic",
      fmt::format("bond_coeff 1 {:.12g} {:.12g}", ff.lammps_bond_K(), ff.l0),
      "angle_style cosine/squared",
      fmt::format("angle_coeff 1 {:.12g} {:.12g}", ff.lammps_angle_K(), ff.theta0_deg),
      "dihedral_style multi/harmonic",
      fmt::format("dihedral_coeff 1 {:.12g} {:.12g} {:.12g} {:.12g} {:.12g}", A[0], A[1], A[2],
                  A[3], A[4]),
      "special_bonds lj 0.0 0.0 0.0",
  };
}

} // namespace pnc::md
