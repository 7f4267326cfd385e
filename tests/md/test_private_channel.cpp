// The stage child <-> LAMMPS server channel (private_channel.hpp): a 0600 socket in a 0700
// directory, no abstract-namespace name, peers checked by uid, ancestry and token; a stage
// on 2 ranks still works through it and leaves nothing behind.
#include "pnc/core/error.hpp"
#include "pnc/md/private_channel.hpp"
#include "pnc/md/runner.hpp"

#include "common/temp_dir.hpp"

#include <gtest/gtest.h>

#include <grp.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace pnc::md;
namespace fs = std::filesystem;

namespace {

fs::path tmpdir(const std::string& tag) {
  return pnc::test::fresh_dir("test_channel_" + tag);
}

/// Socket paths listed in /proc/net/unix (abstract names start with '@').
std::vector<std::string> unix_socket_paths() {
  std::ifstream f("/proc/net/unix");
  std::string line;
  std::vector<std::string> v;
  std::getline(f, line); // header
  while (std::getline(f, line)) {
    std::istringstream s(line);
    std::string field, last;
    int n = 0;
    while (s >> field)
      if (++n >= 8) last = field;
    if (n >= 8) v.push_back(last);
  }
  return v;
}

int count_abstract_pnc(const std::vector<std::string>& paths) {
  int n = 0;
  for (const auto& p : paths)
    n += p.rfind("@pnc", 0) == 0;
  return n;
}

int connect_raw(const std::string& path) {
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  std::strncpy(a.sun_path, path.c_str(), sizeof(a.sun_path) - 1);
  if (connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    const int e = errno;
    close(fd);
    errno = e;
    return -1;
  }
  return fd;
}

/// Accepts until a peer passes or `seconds` elapse; -1 if none passed.
int accept_within(PrivateListener& ch, pid_t ancestor, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    const int fd = ch.accept_one(ancestor, 100, 1000);
    if (fd >= 0) return fd;
  }
  return -1;
}

int wait_exit_code(pid_t pid) {
  int st = 0;
  while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(st) ? WEXITSTATUS(st) : 100 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
}

} // namespace

TEST(PrivateChannel, DirectoryIs0700SocketIs0600AndBothGoAway) {
  std::string dir, path;
  {
    PrivateListener ch;
    dir = ch.directory();
    path = ch.socket_path();
    struct stat st {};
    ASSERT_EQ(lstat(dir.c_str(), &st), 0);
    EXPECT_TRUE(S_ISDIR(st.st_mode));
    EXPECT_EQ(st.st_mode & 07777, 0700u);
    EXPECT_EQ(st.st_uid, geteuid());
    ASSERT_EQ(lstat(path.c_str(), &st), 0);
    EXPECT_TRUE(S_ISSOCK(st.st_mode));
    EXPECT_EQ(st.st_mode & 0777, 0600u);
    EXPECT_EQ(fs::path(path).parent_path().string(), dir);
    EXPECT_EQ(ch.token().size(), kTokenChars);
    EXPECT_EQ(ch.token().find_first_not_of("0123456789abcdef"), std::string::npos);
    PrivateListener other;
    EXPECT_NE(other.token(), ch.token()); // fresh randomness per channel
    ch.close();
    EXPECT_FALSE(fs::exists(path));
    EXPECT_FALSE(fs::exists(dir));
    path = other.socket_path();
    dir = other.directory();
  } // the destructor cleans up too
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(dir));
}

TEST(PrivateChannel, NoAbstractNamespaceSocketWhileListening) {
  PrivateListener ch;
  const auto paths = unix_socket_paths();
  // the listener is visible as a file socket (so this check can see sockets at all) ...
  EXPECT_NE(std::find(paths.begin(), paths.end(), ch.socket_path()), paths.end());
  // ... and there is no abstract name anyone could connect to or take over
  EXPECT_EQ(count_abstract_pnc(paths), 0);
}

TEST(PrivateChannel, AnotherUserCannotConnectOrInject) {
  if (geteuid() != 0)
    GTEST_SKIP() << "needs root to run a child as uid/gid 65534 (nobody); not root here";
  PrivateListener ch;
  const std::string path = ch.socket_path(), token = ch.token();
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    // even knowing the socket path and the token, another user gets nowhere
    if (setgroups(0, nullptr) != 0 || setgid(65534) != 0 || setuid(65534) != 0) _exit(3);
    const int fd = connect_raw(path);
    if (fd < 0) _exit(errno == EACCES ? 0 : 2);
    (void)!write(fd, token.data(), token.size());
    (void)!write(fd, "shell touch /tmp/pnc-pwned\n", 27);
    _exit(1);
  }
  EXPECT_EQ(wait_exit_code(pid), 0) << "1: connected, 2: not EACCES, 3: could not drop to nobody";
  EXPECT_EQ(ch.accept_one(getpid(), 300), -1); // nothing reached the listener
  EXPECT_EQ(ch.refused(), 0);
}

TEST(PrivateChannel, PeersWithoutTheTokenAreRefusedAndTheRealPeerGetsThrough) {
  PrivateListener ch;
  const std::string path = ch.socket_path(), token = ch.token();
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    // 1: a wrong token -> the listener closes the connection
    int fd = connect_raw(path);
    if (fd < 0) _exit(10);
    const std::string wrong(kTokenChars, 'a');
    (void)!write(fd, wrong.data(), wrong.size());
    char c;
    if (read(fd, &c, 1) != 0) _exit(11);
    close(fd);
    // 2: no token at all
    fd = connect_raw(path);
    if (fd < 0) _exit(12);
    close(fd);
    // 3: the real peer
    std::string why;
    fd = connect_private(path, token, why);
    if (fd < 0) _exit(13);
    if (read(fd, &c, 1) != 1 || c != 'k') _exit(14);
    _exit(0);
  }
  const int fd = accept_within(ch, getpid(), 8.0);
  ASSERT_GE(fd, 0) << "the real peer was not accepted; last refusal: " << ch.last_refusal();
  EXPECT_EQ(ch.refused(), 2) << ch.last_refusal();
  ASSERT_EQ(write(fd, "k", 1), 1);
  close(fd);
  EXPECT_EQ(wait_exit_code(pid), 0);
}

TEST(PrivateChannel, SameUserProcessOutsideTheMpirunTreeIsRefused) {
  PrivateListener ch;
  const pid_t sleeper = fork(); // stands for the mpirun we forked
  ASSERT_GE(sleeper, 0);
  if (sleeper == 0) {
    pause();
    _exit(0);
  }
  EXPECT_TRUE(is_same_or_descendant(sleeper, sleeper));
  EXPECT_FALSE(is_same_or_descendant(getpid(), sleeper));
  std::string why;
  const int c = connect_private(ch.socket_path(), ch.token(), why); // right token, wrong tree
  ASSERT_GE(c, 0) << why;
  EXPECT_EQ(ch.accept_one(sleeper, 2000), -1);
  EXPECT_EQ(ch.refused(), 1);
  EXPECT_NE(ch.last_refusal().find("does not descend"), std::string::npos) << ch.last_refusal();
  close(c);
  kill(sleeper, SIGKILL);
  wait_exit_code(sleeper);
}

TEST(PrivateChannel, ServerRefusesADirectoryOthersCanReachOrALink) {
  const auto d = tmpdir("server");
  const fs::path open_dir = d / "open";
  fs::create_directory(open_dir);
  chmod(open_dir.c_str(), 0755);
  // a listener in a directory with group/other permissions: the server does not connect
  const int ls = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  const std::string sp = (open_dir / "s").string();
  std::strncpy(a.sun_path, sp.c_str(), sizeof(a.sun_path) - 1);
  ASSERT_EQ(bind(ls, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  ASSERT_EQ(listen(ls, 4), 0);
  std::string why;
  EXPECT_EQ(connect_private(sp, std::string(kTokenChars, '0'), why), -1);
  EXPECT_NE(why.find("permissions"), std::string::npos) << why;
  close(ls);
  // a symbolic link to a real private directory is refused too (lstat, not stat)
  PrivateListener ch;
  const fs::path link = d / "link";
  fs::create_directory_symlink(ch.directory(), link);
  EXPECT_EQ(connect_private((link / "s").string(), ch.token(), why), -1);
  EXPECT_NE(why.find("symbolic link"), std::string::npos) << why;
  EXPECT_EQ(ch.accept_one(getpid(), 100), -1);
  fs::remove_all(d);
}

// End to end on 2 ranks: the body runs while the server is connected. No abstract socket
// exists then, the private directory is already gone (removed once the server connected),
// and a server start that fails leaves no directory behind either.
TEST(PrivateChannel, TwoRankStageUsesThePrivateChannelAndCleansUp) {
  const auto d = tmpdir("e2e");
  const auto tmp = d / "tmp";
  fs::create_directories(tmp);
  const char* old_tmp = std::getenv("TMPDIR");
  const std::string saved = old_tmp ? old_tmp : "";
  setenv("TMPDIR", tmp.c_str(), 1); // the stage child makes its private directory here
  auto channel_dirs = [&tmp] {
    int n = 0;
    for (const auto& e : fs::directory_iterator(tmp))
      n += e.path().filename().string().rfind("pnc-lmp-", 0) == 0;
    return n;
  };
  const std::string seen = (d / "seen.txt").string();
  const auto o = run_stage({"two ranks", (d / "two.log").string(), {}, 2}, [&](Lammps& l) {
    l.cmd("units lj");
    std::ofstream f(seen);
    f << count_abstract_pnc(unix_socket_paths()) << " " << channel_dirs() << "\n";
  });
  ASSERT_TRUE(o.ok) << o.error;
  int abstract = -1, dirs = -1;
  std::ifstream(seen) >> abstract >> dirs;
  EXPECT_EQ(abstract, 0);
  EXPECT_EQ(dirs, 0);
  // A stand-in server (mpirun runs this script) records what it was given and never
  // connects: the socket was in a 0700 directory under $TMPDIR, the socket 0600, the token
  // in the environment and not in argv; the stage fails and the directory is gone.
  const fs::path fake = d / "fake_server.sh", record = d / "record.txt";
  std::ofstream(fake) << "#!/bin/sh\n"
                         "[ \"$OMPI_COMM_WORLD_RANK\" = 0 ] || exit 0\n"
                         "{ echo \"$1\"; stat -c %a \"$(dirname \"$1\")\"; stat -c %a \"$1\";\n"
                         "  printf %s \"$PNC_LAMMPS_TOKEN\" | wc -c;\n"
                         "  case \"$*\" in *\"$PNC_LAMMPS_TOKEN\"*) echo argv-has-token;;\n"
                         "  *) echo argv-clean;; esac; } > '"
                      << record.string() << "'\n";
  fs::permissions(fake, fs::perms::owner_all);
  setenv("PNC_LAMMPS_SERVER", fake.c_str(), 1);
  const auto bad = run_stage({"no server", (d / "bad.log").string(), {}, 2}, [](Lammps&) {});
  unsetenv("PNC_LAMMPS_SERVER");
  EXPECT_FALSE(bad.ok);
  EXPECT_NE(bad.error.find("before the LAMMPS server connected"), std::string::npos) << bad.error;
  try { // mpirun's failure is a tool failure naming mpirun and its output file
    throw_stage_failure(bad, "stage no server");
    ADD_FAILURE() << "no error";
  } catch (const pnc::ToolError& e) {
    EXPECT_EQ(e.context().tool, "mpirun");
    EXPECT_EQ(e.context().log_path, (d / "bad.log").string() + ".mpirun");
  }
  std::ifstream rec(record);
  std::string sock, dir_mode, sock_mode, token_chars, argv_check;
  std::getline(rec, sock);
  rec >> dir_mode >> sock_mode >> token_chars >> argv_check;
  EXPECT_EQ(sock.rfind((tmp / "pnc-lmp-").string(), 0), 0u) << sock;
  EXPECT_EQ(dir_mode, "700");
  EXPECT_EQ(sock_mode, "600");
  EXPECT_EQ(token_chars, std::to_string(kTokenChars));
  EXPECT_EQ(argv_check, "argv-clean");
  EXPECT_FALSE(sock.empty() || fs::exists(fs::path(sock).parent_path()));
  EXPECT_EQ(channel_dirs(), 0);
  if (old_tmp)
    setenv("TMPDIR", saved.c_str(), 1);
  else
    unsetenv("TMPDIR");
  fs::remove_all(d);
}
