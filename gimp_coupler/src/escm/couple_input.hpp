#pragma once
// The input of `pnc gimp couple`, JSON or TOML by extension (D357; keys and units in docs/escm.md,
// "Input file"): read and checked before LAMMPS starts. Internal to the coupler library
// (escm_run.hpp is the public entry). Units: LAMMPS real for the MD keys (kcal/mol, Angstrom,
// g/mol, fs, K), ps for the schedule, J/m^2 and Pa where the key says so.
#include "pnc/gimp_coupler/escm_run.hpp"

#include "pnc/core/parameters.hpp"

#include <string>

namespace pnc::gimp::escm {

struct CoupleInput {
  double eps = 0.2381, sig = 3.405, rc = 2.5 * 3.405, mass = 39.948;
  bool lj_given = false; ///< the top-level "lj" object is present
  int ncx = 40, ncy = 20, nbx = 14, nby = 14, nz = 3;
  int svc = 2, ivc = 1, substeps = 20;
  double dtau_fs = 4.0;
  std::string mode = "neumann";
  double temperature = 0.0;
  double strain = 1e-2, settle_ps = 10, load_ps = 40, hold_ps = 30, damping_fraction = 0.7;
  int frames = 8;
  double gradient_cells = 1.0;    ///< gradient grid spacing (D79), in cell sizes
  std::string load = "tension_x"; ///< tension_x (Case I), tension_y (Case II), shear (Case III)
  // Cases II/III (D80, D81): edge pre-crack on the line through the block centre.
  bool crack = false;
  int crack_cells = 3;         ///< initial tip in the middle of this cell column (from the left)
  double crack_Gc = 0.0;       ///< J/m^2, growth criterion of the continuum crack; 0: f W_sep (D83)
  double crack_f = 0.2;        ///< LJ epsilon across the crack line / epsilon (weak interface, D83)
  int crack_every = 5;         ///< coupled steps between J evaluations
  double checkpoint_ps = 10.0; ///< simulated time between checkpoints, ps; 0: only at the end
  // MD region kind (md.type, md_region.hpp): "lj" (the FCC crystal, default) or "polymer"
  // (escm_polymer.hpp, D100-D106), and the polymer's build keys.
  std::string md_type = "lj";
  double cell_A = 6.0, slab_A = 16.0, density = -1, poly_T = 300, anneal_ps = 0,
         strain_probe = 1e-2;
  int beads_per_chain = -1, min_beads = 4;
  long md_seed = 1;
  double ff_sigma = -1, ff_epsilon = -1, ff_cutoff_sigma = -1; ///< < 0: rve/ defaults
  bool elastic_given = false;
  double elastic_lambda = 0, elastic_mu = 0; ///< Pa (given by the user)

  /// First cell column and row of the atom block in the continuum.
  int block_x0() const { return (ncx - nbx) / 2; }
  int block_y0() const { return (ncy - nby) / 2; }
};

/// Declares the keys of the input (couple_parameters.cpp, D293), bound to `in`: `top` the top
/// level (with lj and short), else the "short" overrides (every top-level key but lj and short).
/// `crack_given` is set by read() to whether the level has a "crack" table.
void declare_couple_input(Parameters& p, CoupleInput& in, bool top, bool& crack_given);

/// Reads the input and its "short" overrides (with `short_mode`) and checks the geometry and
/// the rules of the MD region kind (MdRegion::check_input), before LAMMPS starts. Throws
/// pnc::InputError naming the file, the key, the value and the rule.
CoupleInput read_couple_input(const std::string& src, bool short_mode);

/// The input file read as JSON (".json" or ".toml", pnc::read_input_file) and printed as compact
/// JSON: what the checkpoint stores and `--resume` compares, so a run started from a TOML
/// file resumes from its JSON conversion and back (D357). Throws InputError like the reader.
std::string read_input_as_json_text(const std::string& path);

/// --resume: the input must be the one the run was started with (`stored`, JSON text from the
/// checkpoint `ckpt`; `now`: read_input_as_json_text), compared as JSON values, except
/// `checkpoint_every_ps` and `comment` (top level and in "short"). The error names the input file
/// and the first key that differs.
void check_same_input(const std::string& src, const std::string& stored, const std::string& now,
                      const std::string& ckpt);

} // namespace pnc::gimp::escm
