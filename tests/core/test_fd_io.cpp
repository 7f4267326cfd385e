// pnc/core/fd_io.hpp: write_fully delivers every byte through short writes and reports a
// refused descriptor; random_hex gives the asked number of hexadecimal characters.
#include "pnc/core/fd_io.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <cctype>
#include <string>
#include <thread>

TEST(FdIo, WriteFullyDeliversMoreThanAPipeHoldsInOneCall) {
  int p[2];
  ASSERT_EQ(::pipe(p), 0);
  // 1 MiB through a pipe of 64 KiB (Linux default): write(2) returns short counts, and the
  // reader must receive every byte in order
  std::string sent(1 << 20, '\0');
  for (std::size_t i = 0; i < sent.size(); ++i)
    sent[i] = static_cast<char>('a' + i % 26);
  std::string got;
  std::thread reader([&] {
    char buf[4096];
    for (ssize_t n; (n = ::read(p[0], buf, sizeof buf)) > 0;)
      got.append(buf, static_cast<std::size_t>(n));
  });
  const bool ok = pnc::write_fully(p[1], sent);
  ::close(p[1]);
  reader.join();
  ::close(p[0]);
  EXPECT_TRUE(ok);
  EXPECT_EQ(got.size(), sent.size());
  EXPECT_TRUE(got == sent);
}

TEST(FdIo, WriteFullyReportsADescriptorThatRefuses) {
  const int fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC); // not open for writing
  ASSERT_GE(fd, 0);
  EXPECT_FALSE(pnc::write_fully(fd, "text"));
  ::close(fd);
  EXPECT_TRUE(pnc::write_fully(fd, "")); // nothing to write: no call made
}

TEST(FdIo, RandomHexHasTheAskedLengthAndDiffers) {
  const std::string a = pnc::random_hex(16), b = pnc::random_hex(16);
  EXPECT_EQ(a.size(), 32u);
  for (char c : a)
    EXPECT_TRUE(std::isxdigit(static_cast<unsigned char>(c)) &&
                !std::isupper(static_cast<unsigned char>(c)))
        << a;
  // 128 random bits: equal values would mean the generator is not random (p = 2^-128)
  EXPECT_NE(a, b);
  EXPECT_EQ(pnc::random_hex(32).size(), 64u);
}
