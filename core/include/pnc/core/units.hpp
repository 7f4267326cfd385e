#pragma once
// Physical constants and unit conversions, the one place pnc spells them (SI, CODATA 2018
// exact values where SI defines them). Every other source uses these names; no literal
// Avogadro number or kcal->J factor appears anywhere else.
//
// LAMMPS "real" units (what pnc's polymer models run in): energy kcal/mol, length Angstrom,
// time fs, pressure atm, mass g/mol, temperature K.

namespace pnc::units {

inline constexpr double avogadro = 6.02214076e23; ///< 1/mol (exact)
inline constexpr double boltzmann = 1.380649e-23; ///< J/K (exact)
inline constexpr double joule_per_kcal = 4184.0;  ///< J/kcal (thermochemical calorie)
inline constexpr double pa_per_atm = 101325.0;    ///< Pa/atm (exact)
inline constexpr double m_per_angstrom = 1e-10;   ///< m/A
inline constexpr double m3_per_angstrom3 = 1e-30; ///< m^3/A^3
inline constexpr double m2_per_angstrom2 = 1e-20; ///< m^2/A^2
inline constexpr double s_per_fs = 1e-15;         ///< s/fs (LAMMPS real time)
inline constexpr double joule_per_kj = 1e3;       ///< J/kJ
inline constexpr double kg_per_g = 1e-3;          ///< kg/g
inline constexpr double kg_m3_per_g_cm3 = 1e3;    ///< (kg/m^3)/(g/cm^3) (densities)
inline constexpr double m_per_mm = 1e-3;          ///< m/mm (the deal.II demo's lengths)
inline constexpr double joule_per_mj = 1e-3;      ///< J/mJ (the deal.II demo's energies)

/// One kcal/mol (per molecule) in J.
inline constexpr double joule_per_kcal_mol = joule_per_kcal / avogadro;
/// J (per molecule) -> kcal/mol.
inline constexpr double kcal_mol_per_joule = avogadro / joule_per_kcal;
/// Boltzmann's constant in kcal/(mol K) as LAMMPS "real" units define it (force->boltz);
/// pnc uses LAMMPS's value so that temperatures it computes match LAMMPS's thermo output.
/// (k_B N_A / 4184 = 0.00198720426, 1.2e-6 relative below it.)
inline constexpr double kB_kcal_mol_K = 0.0019872067;
/// 1 kcal/mol per A^3 in Pa.
inline constexpr double pa_per_kcal_mol_A3 = joule_per_kcal_mol / m3_per_angstrom3;
/// 1 kcal/mol per A^2 in J/m^2.
inline constexpr double j_m2_per_kcal_mol_A2 = joule_per_kcal_mol / m2_per_angstrom2;
/// 1 kcal/mol per A (a force) in N.
inline constexpr double newton_per_kcal_mol_A = joule_per_kcal_mol / m_per_angstrom;
/// 1 kcal/mol times 1 A in J m = N m^2 (a bending stiffness EI).
inline constexpr double j_m_per_kcal_mol_A = joule_per_kcal_mol * m_per_angstrom;
/// One g/mol (per molecule) in kg.
inline constexpr double kg_per_g_mol = kg_per_g / avogadro;
/// 1 A/fs (a LAMMPS real velocity) in m/s (1e5).
inline constexpr double m_per_s_per_angstrom_per_fs = m_per_angstrom / s_per_fs;

} // namespace pnc::units
