#include "io/confined_folder.h"

#include <fcntl.h>
#include <linux/openat2.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <random>
#include <system_error>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "io/io_util.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

std::string errno_message(int e) { return std::generic_category().message(e); }

// Closes a descriptor when it goes out of scope.
struct Fd {
  int fd = -1;
  explicit Fd(int f) : fd(f) {}
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int release() { return std::exchange(fd, -1); }
};

// Whether openat2 is worth trying: false once the kernel (or a seccomp filter) said ENOSYS.
std::atomic<bool> g_have_openat2{true};

int open_with_openat2(int dirfd, const fs::path& relative, int flags) {
  open_how how{};
  how.flags = uint64_t(flags);
  how.resolve = RESOLVE_BENEATH | RESOLVE_NO_SYMLINKS | RESOLVE_NO_MAGICLINKS;
  for (;;) {
    const long r = ::syscall(SYS_openat2, dirfd, relative.c_str(), &how, sizeof how);
    if (r >= 0) return int(r);
    if (errno == EINTR) continue;
    // (EAGAIN: a rename elsewhere on the machine raced the lookup; the kernel asks to retry.)
    if (errno == EAGAIN) continue;
    return -errno;
  }
}

bool is_symlink_at(int dirfd, const std::string& name) {
  struct stat st {};
  return ::fstatat(dirfd, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISLNK(st.st_mode);
}

}  // namespace

int open_beneath_by_walk(int dirfd, const fs::path& relative, int flags) {
  if (relative.empty() || relative.is_absolute()) return -EXDEV;
  std::vector<std::string> parts;
  for (const fs::path& p : relative) parts.push_back(p.string());
  for (const std::string& p : parts)
    if (p.empty() || p == "." || p == "..") return -EXDEV;
  Fd here(-1);
  int at = dirfd;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    const int next =
        ::openat(at, parts[i].c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (next < 0) return errno == ENOTDIR && is_symlink_at(at, parts[i]) ? -ELOOP : -errno;
    Fd hold(next);
    std::swap(here.fd, hold.fd);
    at = here.fd;
  }
  const int fd = ::openat(at, parts.back().c_str(), flags | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return errno == ENOTDIR && is_symlink_at(at, parts.back()) ? -ELOOP : -errno;
  return fd;
}

ConfinedFolder::ConfinedFolder(const fs::path& folder)
    : path_(fs::absolute(folder).lexically_normal()) {
  if (path_.has_relative_path() && !path_.has_filename()) path_ = path_.parent_path();
  fd_ = ::open(path_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0)
    throw std::system_error(errno, std::generic_category(),
                            "cannot open the folder " + path_.string());
}

ConfinedFolder::ConfinedFolder(int fd, fs::path folder) : fd_(fd), path_(std::move(folder)) {}

ConfinedFolder::~ConfinedFolder() {
  if (fd_ >= 0) ::close(fd_);
}

std::optional<fs::path> ConfinedFolder::relative(const fs::path& file) const {
  const fs::path abs = fs::absolute(file).lexically_normal();
  const fs::path rel = abs.lexically_relative(path_);
  if (rel.empty() || *rel.begin() == ".." || rel == ".") return std::nullopt;
  return rel;
}

int ConfinedFolder::open_beneath(const fs::path& relative, int flags) const {
  if (flags & O_CREAT) return -EINVAL;
  if (g_have_openat2.load(std::memory_order_relaxed)) {
    const int r = open_with_openat2(fd_, relative, flags | O_CLOEXEC);
    if (r != -ENOSYS) return r;
    g_have_openat2 = false;
  }
  return open_beneath_by_walk(fd_, relative, flags);
}

std::optional<std::string> ConfinedFolder::write_atomic(const std::string& name,
                                                        std::string_view bytes) const {
  if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos ||
      name.find('\0') != std::string::npos)
    return "not a file name in the folder";
  struct stat st {};
  if (::fstatat(fd_, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0) {
    if (S_ISLNK(st.st_mode)) return "it is a symbolic link";
    if (!S_ISREG(st.st_mode)) return "it is not a regular file";
  }
  io_detail::remove_stale_temporaries_at(fd_, name);
  std::random_device rd;
  std::string tmp;
  int fd = -1;
  for (int attempt = 0; fd < 0 && attempt < 8; ++attempt) {
    tmp = io_detail::temporary_name(name, (uint64_t(rd()) << 32) ^ rd());
    fd = ::openat(fd_, tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) return "cannot create a temporary file: " + errno_message(errno);
  Fd file(fd);
  const auto failed = [&](const char* step, int e) {
    ::unlinkat(fd_, tmp.c_str(), 0);
    return fmt::format("{} failed: {}", step, errno_message(e));
  };
  for (size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return failed("write", errno);
    done += size_t(n);
  }
  if (::fsync(fd) != 0) return failed("fsync", errno);
  if (::close(file.release()) != 0) return failed("close", errno);
  if (::renameat(fd_, tmp.c_str(), fd_, name.c_str()) != 0) return failed("rename", errno);
  ::fsync(fd_);  // (the data is safe already; this persists the rename)
  return std::nullopt;
}

}  // namespace anamorph
