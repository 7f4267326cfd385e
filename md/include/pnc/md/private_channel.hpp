#pragma once
// pnc/md/private_channel.hpp: the link between a stage child and its LAMMPS server.
//
// A stage on K > 1 ranks (runner.hpp) talks to `mpirun -np K pnc_lammps_server` over a Unix
// socket that only the intended peer can use:
//  - the socket is a file (mode 0600) in a fresh private directory made by mkdtemp (mode
//    0700, owned by us) under $TMPDIR when the socket path fits in sun_path, else /tmp; no
//    abstract-namespace name exists, so nothing shows up in /proc/net/unix for others to
//    take over, and another user cannot even reach the socket (EACCES on the directory);
//  - the listener (pnc) accepts a peer only if SO_PEERCRED says it runs as our uid and its
//    pid is the mpirun we forked or a descendant of it (ppid chain in /proc/<pid>/stat; for a
//    stage launched by srun inside a Slurm job: a process of the same job), and
//    only if it first sends the random token (32 bytes from getrandom, 64 hex digits) that
//    pnc passed to mpirun in the environment (PNC_LAMMPS_TOKEN; /proc/<pid>/environ is
//    readable by the owner only, unlike argv). A refused peer is closed and the listener keeps
//    waiting for the real one;
//  - the server side checks, before connecting, that the socket's directory is owned by its
//    uid and has no group/other permission bits (lstat: a symbolic link is refused), and after
//    connecting that the listener runs as its uid (SO_PEERCRED); then it sends the token.
// The directory and socket are removed when the listener is closed or destroyed (also when a
// stage fails with an exception).
#include <sys/types.h>

#include <string>

namespace pnc::md {

/// Environment variable through which pnc hands the token to the LAMMPS server.
inline constexpr const char* kLammpsTokenEnv = "PNC_LAMMPS_TOKEN";
/// Length of the token in characters (32 random bytes as lowercase hex).
inline constexpr std::size_t kTokenChars = 64;

/// 32 bytes from getrandom(2) as 64 lowercase hex digits. Throws pnc::InputError if the
/// kernel gives no random bytes.
std::string random_token();

/// True when `pid` is `ancestor` or one of its descendants (walks the ppid chain in
/// /proc/<pid>/stat; false when a process on the chain is gone).
bool is_same_or_descendant(pid_t pid, pid_t ancestor);

/// True when process `pid` belongs to the Slurm job this process runs in: its environment
/// (/proc/<pid>/environ, readable by the owner only) has our $SLURM_JOB_ID. The check that
/// replaces descent from the launcher for `srun` stages, whose tasks are started by
/// slurmstepd (decision D244). False outside a Slurm job.
bool in_our_slurm_job(pid_t pid);

/// The listening side: a private directory with one socket in it, and the expected token.
class PrivateListener {
public:
  /// Creates the directory (0700) and the listening socket (0600). Throws pnc::InputError
  /// naming the directory when that fails.
  PrivateListener();
  ~PrivateListener();
  PrivateListener(const PrivateListener&) = delete;
  PrivateListener& operator=(const PrivateListener&) = delete;

  const std::string& directory() const { return dir_; }
  const std::string& socket_path() const { return path_; }
  const std::string& token() const { return token_; }

  /// Waits up to `timeout_ms` for one connection and checks it: same uid, pid is `ancestor`
  /// or a descendant of it (`ancestor` <= 0: a task of our Slurm job, in_our_slurm_job), and
  /// the token arrives within `token_timeout_ms`. Returns the
  /// connected socket (close-on-exec) when the peer passes, else -1 (nothing came, or the
  /// peer was refused and closed: see refused()).
  int accept_one(pid_t ancestor, int timeout_ms, int token_timeout_ms = 2000);
  /// How many peers were refused so far.
  int refused() const { return refused_; }
  /// Why the last peer was refused (empty if none was).
  const std::string& last_refusal() const { return last_refusal_; }
  /// Closes the listening socket and removes the socket file and the directory (idempotent).
  void close();

private:
  std::string dir_, path_, token_, last_refusal_;
  int fd_ = -1;
  int refused_ = 0;
};

/// The connecting side (the LAMMPS server's rank 0): checks the directory of `socket_path`
/// (a real directory owned by our uid, no group/other permissions), connects, checks that the
/// listener runs as our uid and sends `token`. Returns the connected socket, or -1 with the
/// reason in `why`.
int connect_private(const std::string& socket_path, const std::string& token, std::string& why);

} // namespace pnc::md
