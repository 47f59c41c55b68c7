// AtomicFile: a uniquely named temporary file beside the target, written in pieces, fsync, then
// rename(2), so readers see either the old file or the complete new one, never a partial write.
//
// Targets that are not plain files: a symbolic link is followed (the link stays and its target
// is replaced); an existing device, FIFO or socket (/dev/null, /dev/stdout, a pipe) is written
// directly, since it can be neither replaced atomically nor should be; so is the file the process's
// standard output or error already is (`-o /dev/stdout > out.png`: the shell's file, at the
// shell's offset); a directory and a read-only file are errors. A target that cannot seek (a pipe)
// gets a format that seeks (EXR fills in its offset table last) through an unnamed spool file.
// Temporary files are registered for removal by a signal handler (io/temporary_files.h); those
// left by a process that was killed (SIGKILL, power loss) are removed by the next write of the
// same target.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "io/image_io.h"
#include "io/io_util.h"
#include "io/temporary_files.h"
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

}  // namespace

namespace {

// The standard stream (1 or 2) that `st` is, or -1.
int standard_stream_of(const struct stat& st) {
  for (int fd : {STDOUT_FILENO, STDERR_FILENO}) {
    struct stat s {};
    if (::fstat(fd, &s) == 0 && s.st_dev == st.st_dev && s.st_ino == st.st_ino) return fd;
  }
  return -1;
}

}  // namespace

bool AtomicFile::writes_directly(const fs::path& file) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0 || S_ISDIR(st.st_mode)) return false;
  return !S_ISREG(st.st_mode) || standard_stream_of(st) >= 0;
}

AtomicFile::AtomicFile(const fs::path& file, Access access) : target_(resolve_links(file)) {
  using io_detail::fail;
  if (has_nul(file.native())) fail("cannot write", file, nul_in_path_message(file.native(), false));
  if (!target_.has_filename()) fail("cannot write", file, "the path does not name a file");
  struct stat st {};
  // (Through `file` itself: /dev/stdout -> /proc/self/fd/1 -> "pipe:[...]" is no path.)
  if (::stat(file.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) fail("cannot write", file, "it is a directory");
    const int stream = standard_stream_of(st);
    if (!S_ISREG(st.st_mode) || stream >= 0) {  // a device, FIFO, socket or our own stream
      open_direct(file, stream, access);
      return;
    }
    // rename(2) would replace it regardless (and root may write anything): a file made
    // read-only is kept as it is.
    if ((st.st_mode & 0222) == 0 || ::access(file.c_str(), W_OK) != 0)
      fail("cannot write", file,
           fmt::format("it is read-only (mode {:04o}); make it writable or choose another name",
                       st.st_mode & 07777));
  }
  // Missing parent directories are created rather than reported: `-o renders/today/a.exr`
  // should simply work, and creating a directory cannot damage anything that exists.
  dir_ = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec)
    fail("cannot write", file,
         fmt::format("cannot create directory '{}': {}", dir_.string(), ec.message()));
  if (const int dfd = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
    io_detail::remove_stale_temporaries_at(dfd, target_.filename().string());
    ::close(dfd);
  }

  // Same directory as the target, so rename(2) stays on one file system and is atomic.
  std::random_device rd;
  for (int attempt = 0; fd_ < 0 && attempt < 8; ++attempt) {
    const uint64_t r = (uint64_t(rd()) << 32) ^ rd();
    tmp_ = dir_ / io_detail::temporary_name(target_.filename().string(), r);
    slot_ = register_temporary(tmp_);  // (before it exists: a signal may come at any moment)
    fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ >= 0) break;
    const int e = errno;
    unregister_temporary(slot_);
    slot_ = -1;
    if (e != EEXIST) {
      errno = e;
      break;
    }
  }
  if (fd_ < 0)
    fail("cannot write", file,
         fmt::format("cannot create a temporary file in '{}': {}", dir_.string(),
                     errno_message(errno)));
}

void AtomicFile::open_direct(const fs::path& file, int stream, Access access) {
  using io_detail::fail;
  sink_ = stream >= 0 ? ::fcntl(stream, F_DUPFD_CLOEXEC, 0)
                      : ::open(file.c_str(), O_WRONLY | O_CLOEXEC);
  if (sink_ < 0) fail("cannot write", file, errno_message(errno));
  direct_ = true;
  target_ = file;  // (for messages: /proc/self/fd/1 may name no path)
  fd_ = sink_;
  if (access == Access::Seeks && ::lseek(sink_, 0, SEEK_CUR) < 0 && errno == ESPIPE) {
    // An unnamed file (gone with the process, whatever ends it), copied out by commit().
    fd_ = ::open(fs::temp_directory_path().c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
    if (fd_ < 0)
      fail("cannot write", file,
           fmt::format("cannot create a spool file for it: {}", errno_message(errno)));
  }
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (sink_ >= 0 && sink_ != fd_) ::close(sink_);
  if (!committed_ && !direct_ && !tmp_.empty()) ::unlink(tmp_.c_str());
  unregister_temporary(slot_);
}

namespace {

// All of `size` bytes to `fd`; errno on failure.
bool write_all(int fd, const char* p, size_t size) {
  for (size_t left = size; left > 0;) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    p += n;
    left -= size_t(n);
  }
  return true;
}

}  // namespace

void AtomicFile::write(const void* bytes, size_t size) {
  if (!write_all(fd_, static_cast<const char*>(bytes), size))
    io_detail::fail("cannot write", target_, fmt::format("write failed: {}", errno_message(errno)));
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

void AtomicFile::copy_spool() {
  std::vector<char> buf(size_t(1) << 20);
  if (::lseek(fd_, 0, SEEK_SET) < 0)
    io_detail::fail("cannot write", target_, fmt::format("seek failed: {}", errno_message(errno)));
  for (;;) {
    const ssize_t n = ::read(fd_, buf.data(), buf.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0)
      io_detail::fail("cannot write", target_,
                      fmt::format("reading the spool failed: {}", errno_message(errno)));
    if (n == 0) break;
    if (!write_all(sink_, buf.data(), size_t(n)))
      io_detail::fail("cannot write", target_,
                      fmt::format("write failed: {}", errno_message(errno)));
  }
  ::close(fd_);
  fd_ = sink_;
}

void AtomicFile::commit() {
  const auto fail_step = [&](const char* step, int err) {
    io_detail::fail("cannot write", target_,
                    fmt::format("{} failed: {}", step, errno_message(err)));
  };
  if (direct_) {
    if (fd_ != sink_) copy_spool();
    const int fd = sink_;
    sink_ = fd_ = -1;
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
  unregister_temporary(slot_);
  slot_ = -1;
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
