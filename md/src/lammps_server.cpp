// The LAMMPS server for stages on K MPI ranks (see lammps_server.hpp).
#define LAMMPS_LIB_MPI
#include "pnc/md/lammps_server.hpp"

#include "lammps_wire.hpp"
#include "pnc/md/private_channel.hpp"

#include <lammps/library.h>
#include <mpi.h>

#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace pnc::md {

namespace wire {

bool write_all(int fd, const void* p, std::size_t n) {
  const char* c = static_cast<const char*>(p);
  while (n > 0) {
    const ssize_t w = send(fd, c, n, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    c += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

bool read_all(int fd, void* p, std::size_t n) {
  char* c = static_cast<char*>(p);
  while (n > 0) {
    const ssize_t r = recv(fd, c, n, 0);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    c += r;
    n -= static_cast<std::size_t>(r);
  }
  return true;
}

bool write_frame(int fd, const std::vector<char>& bytes) {
  const auto n = static_cast<std::uint32_t>(bytes.size());
  return write_all(fd, &n, 4) && write_all(fd, bytes.data(), bytes.size());
}

bool read_frame(int fd, std::vector<char>& bytes) {
  std::uint32_t n = 0;
  if (!read_all(fd, &n, 4)) return false;
  bytes.resize(n);
  return read_all(fd, bytes.data(), n);
}

std::vector<double> local_compute_rows(void* h, const std::string& id, bool& ok) {
  auto* rows =
      static_cast<int*>(lammps_extract_compute(h, id.c_str(), LMP_STYLE_LOCAL, LMP_SIZE_ROWS));
  auto* cols =
      static_cast<int*>(lammps_extract_compute(h, id.c_str(), LMP_STYLE_LOCAL, LMP_SIZE_COLS));
  auto* v =
      static_cast<double*>(lammps_extract_compute(h, id.c_str(), LMP_STYLE_LOCAL, LMP_TYPE_VECTOR));
  const int n = rows ? *rows : 0;
  ok = rows && cols && *cols == 0 && (n == 0 || v); // a local vector, not an array
  if (!ok || n <= 0) return {};
  return std::vector<double>(v, v + n);
}

double global_double(void* h, const std::string& name, bool& ok) {
  auto* p = lammps_extract_global_datatype(h, name.c_str()) == LAMMPS_DOUBLE
                ? static_cast<double*>(lammps_extract_global(h, name.c_str()))
                : nullptr;
  ok = p != nullptr;
  return p ? *p : 0.0;
}

} // namespace wire

namespace {

/// kLocal on every rank: each rank's rows of the local vector, gathered to rank 0 in rank order
/// (MPI_Gatherv); status 1 when a rank has no such local vector, 2 when there are too many rows.
/// The order of the rows depends on the domain decomposition: only sums over them are meant
/// to be used, which agree with one rank's to round-off (D324).
char gather_local_rows(void* h, const std::string& id, int rank, std::vector<double>& out) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  bool ok = false;
  const std::vector<double> mine = wire::local_compute_rows(h, id, ok);
  const int n = static_cast<int>(mine.size());
  int bad = ok ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  std::vector<int> counts(static_cast<std::size_t>(size)), displs(counts.size());
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::size_t total = 0;
  for (std::size_t k = 0; k < counts.size(); ++k)
    total += static_cast<std::size_t>(counts[k]);
  long long big = rank == 0 && total > wire::kMaxLocalRows ? 1 : 0;
  MPI_Bcast(&big, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  if (bad || big) return bad ? 1 : 2;
  if (rank == 0) {
    for (std::size_t k = 1; k < counts.size(); ++k)
      displs[k] = displs[k - 1] + counts[k - 1];
    out.resize(total);
  }
  MPI_Gatherv(mine.data(), n, MPI_DOUBLE, out.data(), counts.data(), displs.data(), MPI_DOUBLE, 0,
              MPI_COMM_WORLD);
  return 0;
}

int env_int(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : -1;
}

std::vector<char> answer(char status, const std::vector<double>& v) {
  std::vector<char> b(1 + v.size() * sizeof(double));
  b[0] = status;
  if (!v.empty()) std::memcpy(b.data() + 1, v.data(), v.size() * sizeof(double));
  return b;
}

} // namespace

LauncherInfo launcher_from_environment() {
  LauncherInfo l;
  int size = env_int("OMPI_COMM_WORLD_SIZE"), rank = env_int("OMPI_COMM_WORLD_RANK");
  if (size < 0) size = env_int("PMI_SIZE"), rank = env_int("PMI_RANK");
  if (size > 1 && rank >= 0) l.size = size, l.rank = rank;
  return l;
}

int serve_lammps(const std::string& socket_path, const std::vector<std::string>& lammps_args) {
  // the token is read and removed from the environment before anything else runs (LAMMPS
  // `shell` or a child process would otherwise inherit it)
  const char* t = std::getenv(kLammpsTokenEnv);
  const std::string token = t ? t : "";
  unsetenv(kLammpsTokenEnv);
  MPI_Init(nullptr, nullptr);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int fd = -1;
  if (rank == 0) {
    std::string why;
    if (token.size() != kTokenChars)
      why = std::string("no valid token in ") + kLammpsTokenEnv;
    else
      fd = connect_private(socket_path, token, why);
    if (fd < 0) {
      std::fprintf(stderr, "pnc lammps server: cannot connect to socket '%s': %s\n",
                   socket_path.c_str(), why.c_str());
      MPI_Abort(MPI_COMM_WORLD, 2);
    }
  }
  std::vector<std::string> args = {"pnc"};
  args.insert(args.end(), lammps_args.begin(), lammps_args.end());
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  void* h = lammps_open(static_cast<int>(argv.size()), argv.data(), MPI_COMM_WORLD, nullptr);
  std::vector<char> frame;
  for (;;) {
    std::uint32_t n = 0;
    if (rank == 0) {
      if (!wire::read_frame(fd, frame)) {
        // the stage child is gone (killed or crashed): take every rank down with it
        std::fprintf(stderr, "pnc lammps server: client closed the connection; aborting\n");
        MPI_Abort(MPI_COMM_WORLD, 3);
      }
      n = static_cast<std::uint32_t>(frame.size());
    }
    MPI_Bcast(&n, 1, MPI_UINT32_T, 0, MPI_COMM_WORLD);
    frame.resize(n);
    MPI_Bcast(frame.data(), static_cast<int>(n), MPI_CHAR, 0, MPI_COMM_WORLD);
    const wire::Request r = wire::decode(frame);
    std::vector<double> out;
    char status = 0;
    switch (r.op) {
    case wire::kCommand:
      lammps_command(h, r.text.c_str());
      break;
    case wire::kFile:
      lammps_file(h, r.text.c_str());
      break;
    case wire::kThermo:
      out = {lammps_get_thermo(h, r.text.c_str())};
      break;
    case wire::kNatoms:
      out = {lammps_get_natoms(h)};
      break;
    case wire::kFix: {
      const int type = r.j < 0 ? LMP_TYPE_VECTOR : LMP_TYPE_ARRAY;
      auto* p = static_cast<double*>(
          lammps_extract_fix(h, r.text.c_str(), LMP_STYLE_GLOBAL, type, r.i, r.j < 0 ? 0 : r.j));
      if (p) {
        out = {*p};
        lammps_free(p);
      } else {
        status = 1;
      }
      break;
    }
    case wire::kCompute: {
      auto* p = static_cast<double*>(lammps_extract_compute(
          h, r.text.c_str(), LMP_STYLE_GLOBAL, r.i < 0 ? LMP_TYPE_SCALAR : LMP_TYPE_VECTOR));
      if (p)
        out = {r.i < 0 ? *p : p[r.i]};
      else
        status = 1;
      break;
    }
    case wire::kGather: {
      out.resize(static_cast<std::size_t>(lammps_get_natoms(h)) * static_cast<std::size_t>(r.i));
      std::string name = r.text;
      lammps_gather_atoms(h, name.data(), 1, r.i, out.data());
      break;
    }
    case wire::kBox: {
      double lo[3], hi[3], xy, yz, xz;
      int periodicity[3], changed;
      lammps_extract_box(h, lo, hi, &xy, &yz, &xz, periodicity, &changed);
      out = {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], xy, yz, xz};
      break;
    }
    case wire::kLocal:
      status = gather_local_rows(h, r.text, rank, out);
      break;
    case wire::kVersion:
      out = {static_cast<double>(lammps_version(h))};
      break;
    case wire::kGlobal: {
      bool ok = false;
      out = {wire::global_double(h, r.text, ok)};
      status = ok ? 0 : 1;
      break;
    }
    default: // quit (or a malformed request)
      if (rank == 0) wire::write_frame(fd, answer(0, {}));
      lammps_close(h);
      if (fd >= 0) close(fd);
      MPI_Finalize();
      return 0;
    }
    if (rank == 0 && !wire::write_frame(fd, answer(status, out))) {
      std::fprintf(stderr, "pnc lammps server: client closed the connection; aborting\n");
      MPI_Abort(MPI_COMM_WORLD, 3);
    }
  }
}

} // namespace pnc::md
