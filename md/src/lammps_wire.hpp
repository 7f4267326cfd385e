#pragma once
// Internal: the framing of requests and answers between a stage child and the LAMMPS server
// (lammps_server.hpp). A frame is a uint32 byte count and the bytes. A request carries an
// operation letter, two ints and a string; an answer a status byte and doubles.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace pnc::md::wire {

enum Op : char {
  kCommand = 'c',
  kFile = 'f',
  kThermo = 't',
  kNatoms = 'n',
  kFix = 'x',
  kCompute = 'k',
  kGather = 'g',
  kBox = 'b',
  kLocal = 'l',   // the rows of a compute's local vector, gathered from every rank (D324)
  kGlobal = 'd',  // a global double of LAMMPS by name (D324)
  kVersion = 'v', // the release date of the LAMMPS library (D366)
  kQuit = 'q'
};

struct Request {
  char op = kQuit;
  std::int32_t i = 0, j = 0;
  std::string text;
};

inline std::vector<char> encode(const Request& r) {
  std::vector<char> b(1 + 8 + r.text.size());
  b[0] = r.op;
  std::memcpy(b.data() + 1, &r.i, 4);
  std::memcpy(b.data() + 5, &r.j, 4);
  std::memcpy(b.data() + 9, r.text.data(), r.text.size());
  return b;
}

inline Request decode(const std::vector<char>& b) {
  Request r;
  if (b.size() < 9) return r; // malformed: quit
  r.op = b[0];
  std::memcpy(&r.i, b.data() + 1, 4);
  std::memcpy(&r.j, b.data() + 5, 4);
  r.text.assign(b.data() + 9, b.size() - 9);
  return r;
}

/// Writes all of `n` bytes; false when the peer is gone.
bool write_all(int fd, const void* p, std::size_t n);
/// Reads exactly `n` bytes; false on end of stream or error.
bool read_all(int fd, void* p, std::size_t n);
bool write_frame(int fd, const std::vector<char>& bytes);
bool read_frame(int fd, std::vector<char>& bytes);

/// At most this many rows of a local compute in one answer (its frame must stay below 4 GiB).
constexpr std::size_t kMaxLocalRows = (std::size_t{1} << 29) - 1;
/// This rank's rows of the local vector of compute `id` (computed now if stale); `ok` false
/// when `id` names no compute with a local vector (D324). Used in-process and by the server.
std::vector<double> local_compute_rows(void* h, const std::string& id, bool& ok);
/// The global double `name` of LAMMPS (lammps_extract_global); `ok` false when LAMMPS has no
/// global double of that name.
double global_double(void* h, const std::string& name, bool& ok);

} // namespace pnc::md::wire
