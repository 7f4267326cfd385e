#pragma once
// Test helper: stand-ins for Slurm's sbatch, scontrol and squeue in a test's own scratch
// directory, for the tests of what a planned command submits without a cluster (the jobs never
// run). sbatch appends its arguments to <dir>/sbatch.args (one line per job) and prints the job
// id 77; scontrol (release) and squeue (an empty queue) succeed silently.
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

namespace pnc::test {

/// Writes the stand-ins into <dir>/bin (owner-only) and returns the prefix of a shell command
/// line that puts them first on PATH ("PATH=<dir>/bin:\"$PATH\" ").
inline std::string slurm_stand_ins(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  const fs::path bin = dir / "bin";
  fs::create_directories(bin);
  const std::string log = (dir / "sbatch.args").string();
  for (const auto& [name, text] :
       {std::pair<std::string, std::string>{"sbatch", "echo \"$@\" >> '" + log + "'\necho 77"},
        {"scontrol", "exit 0"},
        {"squeue", "exit 0"}}) {
    std::ofstream(bin / name) << "#!/bin/sh\n" << text << "\n";
    fs::permissions(bin / name, fs::perms::owner_all);
  }
  return "PATH=" + bin.string() + ":\"$PATH\" ";
}

} // namespace pnc::test
