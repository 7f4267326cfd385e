#pragma once
// pnc/core/run_dir.hpp: the one policy for the output directory of a long command
// (`pnc characterize`, `pnc thermo ti|persistence`, `pnc gimp run|couple`).
//
// 1. One process per directory. RunDirLock takes an exclusive advisory lock (flock(2)) on
//    `<dir>/.pnc.lock` for the whole run and writes the holder's pid and command line into it.
//    A second pnc process on the same directory is refused at once with an InputError naming
//    the directory and the holder's pid and command. The lock ends with the process (also on
//    kill -9): no stale lock is ever left; the file itself stays (removing it would race).
//    The lock file is opened with O_NOFOLLOW|O_CLOEXEC: a symbolic link there is refused, and
//    programs pnc executes (python, mpirun) do not inherit it; stage children that pnc forks
//    (pnc::rve) do, so the directory stays locked while one of them runs.
// 2. An existing run is continued only with --resume. refuse_existing_run() refuses a
//    directory holding any of a command's run markers (checkpoint, summary, ...) without
//    --resume, with the same message form for every command.
// 3. --resume continues a run only with the input it was started with, compared canonically
//    (require_same_input: parsed values, so whitespace, number spelling and key order do not
//    matter), and a difference is refused naming the first key that differs (D339).
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pnc {

class RunDirLock {
public:
  /// Creates `dir` if needed (make_output_directory) and locks it for this process.
  /// `command` is recorded for the message another process gets. Throws InputError (source
  /// `dir`, field `field`) when another process holds the lock or the lock file is unusable.
  RunDirLock(const std::string& dir, const std::string& command,
             const std::string& field = "--out");
  ~RunDirLock();
  RunDirLock(const RunDirLock&) = delete;
  RunDirLock& operator=(const RunDirLock&) = delete;

  /// `<dir>/.pnc.lock`
  static std::string lock_path(const std::string& dir);

private:
  int fd_ = -1;
};

/// Without `resume`, throws InputError (source `dir`, field `field`, value `dir`) when `dir`
/// holds any of `markers` (paths relative to `dir`): "already holds a run (<marker>): add
/// --resume to continue it, or use a new --out directory".
void refuse_existing_run(const std::string& dir, bool resume,
                         const std::vector<std::string>& markers,
                         const std::string& field = "--out");

/// --resume: throws InputError (source `src`, the input file; field: the first key that
/// differs, dotted for nested objects, "[i]" for arrays; value: its value now) unless `now`
/// equals `stored`, the input the run was started with as kept in `stored_in` (a checkpoint).
/// Both are compared as JSON values: whitespace, key order and number spelling do not matter.
/// `may_change` ("" or e.g. "comment and checkpoint_every_ps") is named in the message; the
/// caller removes those keys from both before the call.
/// `flag`: the option that continues the run (--resume, or --refit of pnc characterize, D400).
void require_same_input(const std::string& src, const nlohmann::json& stored,
                        const nlohmann::json& now, const std::string& stored_in,
                        const std::string& may_change = "", const std::string& flag = "--resume");

} // namespace pnc
