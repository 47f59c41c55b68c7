#include "io/read_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

namespace anamorph {

std::optional<ReadFailure> read_whole_file(const std::filesystem::path& file,
                                           std::vector<unsigned char>* out) {
  out->clear();
  // open(2) would read the name only up to a NUL (callers say so first; this is the last guard).
  if (file.native().find('\0') != std::string::npos) return ReadFailure{"open", EINVAL};
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return ReadFailure{"open", errno};
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) return ReadFailure{"read", errno};
  if (S_ISDIR(st.st_mode)) return ReadFailure{"open", EISDIR};
  // The size is a hint (a pipe has none, a file may grow); the data ends where read(2) says.
  out->resize(size_t(std::max<off_t>(st.st_size, 0)) + 1);
  size_t got = 0;
  for (;;) {
    if (got == out->size()) out->resize(out->size() * 2 + 4096);
    const ssize_t n = ::read(fd, out->data() + got, out->size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return ReadFailure{"read", errno};
    if (n == 0) break;
    got += size_t(n);
  }
  out->resize(got);
  return std::nullopt;
}

}  // namespace anamorph
