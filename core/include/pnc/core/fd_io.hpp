#pragma once
// pnc/core/fd_io.hpp: the small POSIX helpers pnc's own writers share (the run log, the
// recorded LAMMPS input, temporary-file names, the stage server's token).
#include <cstddef>
#include <string>
#include <string_view>

namespace pnc {

/// Writes all of `bytes` to the file descriptor `fd` with write(2), retrying on EINTR and
/// short writes. Returns false (errno set by write) when the descriptor refuses more; what was
/// written before stays written.
bool write_fully(int fd, std::string_view bytes);

/// `bytes` random bytes from getrandom(2), as 2*bytes lower-case hexadecimal characters
/// (at most 32 bytes). Throws pnc::InputError naming getrandom when the kernel gives none.
std::string random_hex(std::size_t bytes);

} // namespace pnc
