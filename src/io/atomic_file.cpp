// AtomicFile: a uniquely named temporary file beside the target, written in pieces, fsync, then
// rename(2), so readers see either the old file or the complete new one, never a partial write.
//
// Targets that are not plain files: a symbolic link is followed (the link stays and its target
// is replaced); an existing device, FIFO or socket (/dev/null, /dev/stdout, a pipe) is written
// directly, since it can be neither replaced atomically nor should be; a directory is an error.
// Temporary files left by a process that was killed (SIGKILL, power loss) are removed by the
// next write of the same target.
#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <system_error>

#include <fmt/format.h>

#include "io/image_io.h"
#include "io/io_util.h"
#include "math/user_text.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

std::string errno_message(int e) { return std::generic_category().message(e); }

// The file a write to `file` lands in: symbolic links followed (up to 40, as the kernel does).
fs::path resolve_links(fs::path file) {
  for (int hops = 0; hops < 40; ++hops) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(file, ec))) return file;
    const fs::path target = fs::read_symlink(file, ec);
    if (ec) return file;
    file = target.is_absolute() ? target : file.parent_path() / target;
  }
  io_detail::fail("cannot write", file, "too many levels of symbolic links");
}

// Removes ".NAME.tmp-PID-*" files in dir whose PID is no longer running.
void remove_stale_temporaries(const fs::path& dir, const std::string& name) {
  const std::string prefix = "." + name + ".tmp-";
  DIR* d = ::opendir(dir.c_str());
  if (!d) return;
  while (const dirent* e = ::readdir(d)) {
    const std::string entry = e->d_name;
    if (entry.rfind(prefix, 0) != 0) continue;
    char* end = nullptr;
    const long pid = std::strtol(entry.c_str() + prefix.size(), &end, 10);
    if (pid <= 0 || !end || *end != '-' || pid == ::getpid()) continue;
    if (::kill(pid_t(pid), 0) != 0 && errno == ESRCH) ::unlinkat(::dirfd(d), e->d_name, 0);
  }
  ::closedir(d);
}

}  // namespace

AtomicFile::AtomicFile(const fs::path& file) : target_(resolve_links(file)) {
  using io_detail::fail;
  if (has_nul(file.native())) fail("cannot write", file, nul_in_path_message(file.native(), false));
  if (!target_.has_filename()) fail("cannot write", file, "the path does not name a file");
  struct stat st {};
  if (::stat(target_.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) fail("cannot write", file, "it is a directory");
    if (!S_ISREG(st.st_mode)) {  // a device, FIFO or socket: written as it is
      fd_ = ::open(target_.c_str(), O_WRONLY | O_CLOEXEC);
      if (fd_ < 0) fail("cannot write", file, errno_message(errno));
      direct_ = true;
      return;
    }
  }
  // Missing parent directories are created rather than reported: `-o renders/today/a.exr`
  // should simply work, and creating a directory cannot damage anything that exists.
  dir_ = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec)
    fail("cannot write", file,
         fmt::format("cannot create directory '{}': {}", dir_.string(), ec.message()));
  remove_stale_temporaries(dir_, target_.filename().string());

  // Same directory as the target, so rename(2) stays on one file system and is atomic.
  std::random_device rd;
  for (int attempt = 0; fd_ < 0 && attempt < 8; ++attempt) {
    const uint64_t r = (uint64_t(rd()) << 32) ^ rd();
    tmp_ = dir_ / fmt::format(".{}.tmp-{}-{:016x}", target_.filename().string(), ::getpid(), r);
    fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ < 0 && errno != EEXIST) break;
  }
  if (fd_ < 0)
    fail("cannot write", file,
         fmt::format("cannot create a temporary file in '{}': {}", dir_.string(),
                     errno_message(errno)));
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_ && !direct_ && !tmp_.empty()) ::unlink(tmp_.c_str());
}

void AtomicFile::write(const void* bytes, size_t size) {
  const char* p = static_cast<const char*>(bytes);
  for (size_t left = size; left > 0;) {
    const ssize_t n = ::write(fd_, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      io_detail::fail("cannot write", target_,
                      fmt::format("write failed: {}", errno_message(errno)));
    }
    p += n;
    left -= size_t(n);
  }
}

uint64_t AtomicFile::tell() const {
  const off_t at = ::lseek(fd_, 0, SEEK_CUR);
  if (at < 0)
    io_detail::fail("cannot write", target_, fmt::format("seek failed: {}", errno_message(errno)));
  return uint64_t(at);
}

void AtomicFile::seek(uint64_t offset) {
  if (::lseek(fd_, off_t(offset), SEEK_SET) < 0)
    io_detail::fail("cannot write", target_, fmt::format("seek failed: {}", errno_message(errno)));
}

void AtomicFile::commit_as(const fs::path& other) {
  if (!direct_) target_ = resolve_links(other);
  commit();
}

void AtomicFile::commit() {
  const auto fail_step = [&](const char* step, int err) {
    io_detail::fail("cannot write", target_,
                    fmt::format("{} failed: {}", step, errno_message(err)));
  };
  if (direct_) {
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) fail_step("close", errno);
    committed_ = true;
    return;
  }
  if (::fsync(fd_) != 0) fail_step("fsync", errno);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail_step("close", errno);
  if (::rename(tmp_.c_str(), target_.c_str()) != 0) fail_step("rename over target", errno);
  committed_ = true;
  // Persist the rename itself. The data is already safe, so a failure here is not an error.
  const int dfd = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

void write_file_atomic(const fs::path& file, const void* bytes, size_t size) {
  AtomicFile f(file);
  f.write(bytes, size);
  f.commit();
}

}  // namespace anamorph
