// write_file_atomic: a uniquely named temporary file beside the target, fsync, then rename(2),
// so readers see either the old file or the complete new one, never a partial write.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <random>
#include <system_error>

#include <fmt/format.h>

#include "io/image_io.h"
#include "io/io_util.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {
std::string errno_message(int e) { return std::generic_category().message(e); }
}  // namespace

void write_file_atomic(const fs::path& file, const void* bytes, size_t size) {
  using io_detail::fail;
  if (!file.has_filename()) fail("cannot write", file, "the path does not name a file");
  // Missing parent directories are created rather than reported: `-o renders/today/a.exr`
  // should simply work, and creating a directory cannot damage anything that exists.
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    fail("cannot write", file,
         fmt::format("cannot create directory '{}': {}", dir.string(), ec.message()));

  // Same directory as the target, so rename(2) stays on one file system and is atomic.
  fs::path tmp;
  int fd = -1;
  std::random_device rd;
  for (int attempt = 0; fd < 0 && attempt < 8; ++attempt) {
    const uint64_t r = (uint64_t(rd()) << 32) ^ rd();
    tmp = dir / fmt::format(".{}.tmp-{}-{:016x}", file.filename().string(), ::getpid(), r);
    fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0)
    fail("cannot write", file,
         fmt::format("cannot create a temporary file in '{}': {}", dir.string(),
                     errno_message(errno)));

  int err = 0;
  const char* step = "";
  const char* p = static_cast<const char*>(bytes);
  for (size_t left = size; left > 0;) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      err = errno, step = "write";
      break;
    }
    p += n;
    left -= size_t(n);
  }
  if (!err && ::fsync(fd) != 0) err = errno, step = "fsync";
  if (::close(fd) != 0 && !err) err = errno, step = "close";
  if (!err && ::rename(tmp.c_str(), file.c_str()) != 0) err = errno, step = "rename over target";
  if (err) {
    ::unlink(tmp.c_str());
    fail("cannot write", file, fmt::format("{} failed: {}", step, errno_message(err)));
  }
  // Persist the rename itself. The data is already safe, so a failure here is not an error.
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

}  // namespace anamorph
