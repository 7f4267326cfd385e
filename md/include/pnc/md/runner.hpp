#pragma once
// pnc/md/runner.hpp: run LAMMPS stages in supervised child processes.
//
// Units: whatever the stage's commands set; every stage pnc writes uses LAMMPS `real`.
//
// The Debian LAMMPS library has no C++ exceptions: a LAMMPS error calls exit() in the
// process that hosts LAMMPS. So every stage runs in a child created by fork(); the child
// opens LAMMPS with `-log <stage log> -screen none -nocite`, runs the stage body, writes its
// result files atomically, and _exit(0)s. The parent waits and, when the child did not exit
// with 0, reports the last "ERROR..." line of the stage log (LAMMPS's own message) plus the
// "Last command:" line, or the pnc error the body threw (kept in `<log>.pnc-error` with its
// kind and parts, rebuilt in the parent), or the signal that killed it. The parent never loads
// LAMMPS state and always survives. throw_stage_failure() turns a failed outcome into the
// error of its kind (core/error.hpp): LAMMPS ending the stage is a pnc::ToolError.
//
// The parent must not have initialised MPI (the child does, through lammps_open_no_mpi).
#include "pnc/md/box.hpp"

#include <array>
#include <cstdint>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace pnc::md {

/// LAMMPS's atom id (tagint) and time step (bigint) types of the linked build: the
/// LAMMPS_BIGBIG / LAMMPS_SMALLSMALL definitions come with the LAMMPS::lammps target.
#if defined(LAMMPS_BIGBIG)
using AtomId = std::int64_t;
#else
using AtomId = int;
#endif
#if defined(LAMMPS_SMALLSMALL)
using Step = int;
#else
using Step = std::int64_t;
#endif

/// The local per-atom arrays of an in-process instance, LAMMPS's own storage (no copy), index
/// i < n in LAMMPS's local order: id[i] the atom id, x[i][0..2] position (Angstrom in `real`),
/// v[i][0..2] velocity (Angstrom/fs), f[i][0..2] force (kcal/(mol Angstrom)). Valid until the
/// next command (a run can sort or reallocate them); writes through v, x, f change the atoms.
struct LocalAtoms {
  int n = 0; ///< atoms on this process (LAMMPS "nlocal")
  const AtomId* id = nullptr;
  double** x = nullptr;
  double** v = nullptr;
  double** f = nullptr;
};

/// The callback of a `fix ID external pf/callback` (Lammps::set_external_force), called by
/// LAMMPS at every step the fix applies with the step, the n local atoms, their ids, positions
/// x[i][0..2] (Angstrom in `real`) and fext[i][0..2] to fill (kcal/(mol Angstrom) in `real`,
/// added to the atom's force). It must not throw: an exception escaping it ends the process.
using ExternalForce =
    std::function<void(Step step, int n, const AtomId* id, double** x, double** fext)>;

/// A LAMMPS instance inside a stage child: in the child's own process (1 rank), or the
/// LAMMPS server on K ranks (lammps_server.hpp) behind the same calls. `cmd` runs one
/// command; a LAMMPS error in it terminates the child (or the server; then the next call
/// throws with LAMMPS's ERROR line from the log), and the parent reports it from the log.
class Lammps {
public:
  explicit Lammps(void* handle) : h_(handle) {}
  /// Remote instance: `fd` is the connected socket to the server's rank 0; `log_path` is the
  /// server's LAMMPS log (for the error message when the server ends).
  Lammps(int fd, std::string log_path) : fd_(fd), log_(std::move(log_path)) {}
  ~Lammps();
  /// A LAMMPS instance in this process without MPI (lammps_open_no_mpi) with the command-line
  /// `args` (args[0] the program name, e.g. {"pnc", "-screen", "none", "-log", path}), owned:
  /// closed by the destructor. A pnc::ToolError naming `doing` when LAMMPS gives no instance.
  /// Unlike a stage child's instance it shares the process, so a LAMMPS error ends the caller.
  static std::unique_ptr<Lammps> open_in_process(const std::vector<std::string>& args,
                                                 const std::string& doing);
  Lammps(const Lammps&) = delete;
  Lammps& operator=(const Lammps&) = delete;
  /// From now on every command (and `file` as `include PATH`) is also appended to the LAMMPS
  /// input file `path`, each line written before LAMMPS runs it (so the command that stopped
  /// LAMMPS is its last line); `header` (comment lines) starts the file. Returns false (and
  /// records nothing) when the file cannot be created; a symbolic link there is refused.
  bool record_input(const std::string& path, const std::string& header);
  void cmd(const std::string& command);
  void cmds(const std::vector<std::string>& commands);
  /// Runs a LAMMPS input file (lammps_file).
  void file(const std::string& path);
  double thermo(const char* keyword);
  /// nullptr for a remote instance.
  void* handle() const { return h_; }
  long natoms();
  /// Element of a global vector (i) or array (i, j) of a fix; throws if absent.
  double fix_value(const std::string& id, int i, int j = -1);
  /// Element of a compute's global vector; global scalar when i < 0.
  double compute_value(const std::string& id, int i = -1);
  /// The rows of the local vector of compute `id` (e.g. `compute pair/local dist`) from every
  /// rank; on K ranks each rank's rows go to rank 0 (MPI_Gatherv) in rank order, so the row
  /// order depends on the rank count and only sums over rows are meant (D324). Throws if `id`
  /// is no compute with a local vector.
  std::vector<double> compute_local_vector(const std::string& id);
  /// The release date of this instance's LAMMPS library as the integer YYYYMMDD (LAMMPS's
  /// lammps_version; e.g. 20210929 for "29 Sep 2021"); the case checkpoints record it (D366).
  int version();
  /// A global double of LAMMPS by name (lammps_extract_global), e.g. "nktv2p" (the pressure
  /// unit conversion, atm per (kcal/mol)/A^3 in units real); throws if there is none.
  double extract_global_double(const std::string& name);
  /// Gathers a per-atom double quantity ("x", "v", "f") ordered by atom id, count per atom.
  std::vector<double> gather(const std::string& name, int count);
  /// The current simulation box (Angstrom in `real` units).
  LmpBox box();

  // In-process instance only (a remote one throws std::logic_error, a bug); docs/decisions
  // D346: the one way pnc code outside md/ reaches a LAMMPS instance.
  /// An integer setting of LAMMPS by name (lammps_extract_setting), e.g. "dimension", "nlocal",
  /// "tagint" (bytes); a pnc::InputError naming the setting when LAMMPS knows no such name.
  int extract_setting(const std::string& name);
  /// A global string of LAMMPS by name (lammps_extract_global), e.g. "units" ("real", "lj",
  /// ...); a pnc::InputError naming it when LAMMPS has no global string of that name.
  std::string extract_global_string(const std::string& name);
  /// Periodicity of the box along x, y, z (LAMMPS `boundary p`).
  std::array<bool, 3> periodic();
  /// The atom ids by id order as lammps_gather_atoms gives them: {1, ..., natoms} when the ids
  /// are consecutive from 1 (LAMMPS refuses to gather otherwise and the entries stay 0). A
  /// pnc::ToolError when the build's atom id size differs from AtomId.
  std::vector<AtomId> gather_ids();
  /// The local per-atom arrays (no copy; see LocalAtoms). A pnc::ToolError when one is missing.
  LocalAtoms local_atoms();
  /// The global scalar of fix `id` (e.g. the energy a `fix langevin ... tally yes` removed,
  /// kcal/mol in `real`); a pnc::InputError naming the fix when it has none.
  double fix_scalar(const std::string& id);
  /// Registers `cb` as the callback of the `fix <fix_id> external pf/callback ...` defined
  /// before; the instance keeps it (a later call for the same fix replaces it). A
  /// pnc::InputError naming the fix when there is no fix of that id.
  void set_external_force(const std::string& fix_id, ExternalForce cb);
  /// Remote: asks the server to close LAMMPS and end; no-op in-process.
  void quit();

private:
  /// Remote call: sends the request, returns the answer's doubles; `found` (if given) gets
  /// whether the server found the fix/compute.
  std::vector<double> call(char op, const std::string& text, int i = 0, int j = 0,
                           bool* found = nullptr);
  void record(const std::string& line);
  void* local(const char* what) const; ///< h_, or std::logic_error naming `what` if remote
  void* h_ = nullptr;
  bool owned_ = false; ///< open_in_process: the destructor closes h_
  std::map<std::string, std::unique_ptr<ExternalForce>> external_; ///< by fix id
  int fd_ = -1;
  std::string log_;
  int input_fd_ = -1; ///< record_input's file, or -1
};

struct StageSpec {
  std::string name;                    ///< for messages, e.g. "equilibrate/hot"
  std::string log_path;                ///< LAMMPS log of this stage (overwritten)
  std::vector<std::string> extra_args; ///< extra LAMMPS command-line args, e.g. {"-sf","opt"}
  /// MPI ranks of LAMMPS for this stage. 1: LAMMPS inside the stage child. K > 1: the child
  /// starts `mpirun -np K pnc_lammps_server` (lammps_server.hpp) and drives it; the mpirun's
  /// own output goes to `<log_path>.mpirun`.
  int ranks = 1;
};

struct StageOutcome {
  std::string name;
  bool ok = false;
  int exit_code = 0; ///< child exit status (when it exited)
  int signal = 0;    ///< signal that killed the child, 0 if none
  std::string error; ///< LAMMPS's ERROR line (+ last command) or the pnc error, if !ok
  std::string log_path;
  std::string input_path; ///< its in.<name> (stage_input_path) when the child wrote one, else ""
  double seconds = 0;
  /// The pnc error (InputError, SimulationError, ToolError; any other exception as a
  /// std::runtime_error) the stage body threw in the child, rebuilt in the parent; null when
  /// LAMMPS or a signal ended the child.
  std::exception_ptr child_error;
};

using StageBody = std::function<void(Lammps&)>;

/// `in.<name>` next to the stage's log (characters other than letters, digits, '.', '-' and
/// '_' in the name become '_'): the LAMMPS input every stage leaves, the commands pnc sent in
/// the order LAMMPS ran them, rerunnable with plain `lmp -in` from the directory its header
/// names (docs/decisions/rve.md D247).
std::string stage_input_path(const StageSpec& spec);

/// Runs `body` in a child process with its own LAMMPS instance; blocks until it ends.
StageOutcome run_stage(const StageSpec& spec, const StageBody& body);

/// Runs stages concurrently, at most `jobs` at a time (one child each). Outcomes in input order.
std::vector<StageOutcome> run_stages(const std::vector<std::pair<StageSpec, StageBody>>& stages,
                                     int jobs);

/// Throws the error a failed stage stands for; `stage` names it for the user ("stage
/// equilibrate/hot", "lambda point ref_0.5"), `note` (may be empty) is added to the message.
///  - LAMMPS (or a signal) ended the child: pnc::ToolError("LAMMPS", "running <stage>",
///    LAMMPS's ERROR line + last command, the stage log) - exit code 7;
///  - the body threw a pnc::InputError: InputError(log, stage, "", its message) - exit code 1;
///  - a pnc::SimulationError: the same error, its entity prefixed by the stage - exit code 6;
///  - a pnc::ToolError (e.g. mpirun did not start the server): that error, the stage added to
///    what pnc was doing - exit code 7;
///  - anything else: std::runtime_error naming the stage and log (a bug) - exit code 2.
[[noreturn]] void throw_stage_failure(const StageOutcome& o, const std::string& stage,
                                      const std::string& note = "");

/// The last "ERROR" line of a LAMMPS log with the following "Last command:" line, or "".
std::string last_lammps_error(const std::string& log_path);

} // namespace pnc::md
