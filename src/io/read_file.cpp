#include "io/read_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <system_error>

#include <fmt/format.h>

#include "io/confined_folder.h"

#include "io/read_log.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

thread_local const ReadConfinement* g_confinement = nullptr;

std::string errno_message(int e) { return std::generic_category().message(e); }

std::string size_text(uint64_t bytes) {
  if (bytes < 1024) return fmt::format("{} bytes", bytes);
  const char* units[] = {"KiB", "MiB", "GiB", "TiB"};
  double v = double(bytes) / 1024;
  int u = 0;
  while (v >= 1024 && u < 3) v /= 1024, ++u;
  return fmt::format("{:.1f} {}", v, units[u]);
}

ReadFailure not_regular(unsigned mode) {
  if (S_ISDIR(mode)) return {"open", EISDIR, "is a directory"};
  return {"open", 0, fmt::format("is {}, not a regular file", file_kind_name(mode))};
}

// open(2) of a path the confinement allows (see ReadConfinement), or why not.
std::variant<int, ReadFailure> open_confined(const fs::path& file, const ConfinedFolder& folder,
                                             int flags) {
  const auto outside = [&] {
    return ReadFailure{"open", 0,
                       fmt::format("is outside the scene's folder ({}): the editor reads files "
                                   "only there",
                                   folder.path().string())};
  };
  const std::optional<fs::path> rel = folder.relative(file);
  if (!rel) return outside();
  const int fd = folder.open_beneath(*rel, flags);
  if (fd >= 0) return fd;
  if (fd == -ENXIO) {  // (a socket: named from the file itself, reached the same way)
    const int path = folder.open_beneath(*rel, O_PATH);
    struct stat st {};
    const bool known = path >= 0 && ::fstat(path, &st) == 0;
    if (path >= 0) ::close(path);
    if (known && !S_ISREG(st.st_mode)) return not_regular(st.st_mode);
  }
  if (fd == -EXDEV) return outside();
  if (fd == -ELOOP)
    return ReadFailure{"open", ELOOP,
                       "is reached through a symbolic link: the editor reads only files in the "
                       "scene's folder, and follows no links there"};
  return ReadFailure{"open", -fd, errno_message(-fd)};
}

// A file as ReadConfinement::trusted names it.
std::string confinement_key(const fs::path& file) {
  std::error_code ec;
  return fs::absolute(file, ec).lexically_normal().string();
}

}  // namespace

InputFile::~InputFile() {
  if (fd_ >= 0) ::close(fd_);
}

const char* file_kind_name(unsigned mode) {
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISLNK(mode)) return "a symbolic link";
  return "a regular file";
}

std::variant<InputFile, ReadFailure> open_input(const fs::path& file, const InputKind& kind) {
  // O_NONBLOCK: a FIFO without a writer would block open(2) until one came; a device's open
  // may wait for a carrier. Neither is read: they are refused below, after fstat.
  constexpr int flags = O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC;
  // open(2) would read the name only up to a NUL (callers say so first; this is the last guard).
  if (file.native().find('\0') != std::string::npos)
    return ReadFailure{"open", EINVAL, "the file name holds a NUL character"};
  const ReadConfinement* c = g_confinement;
  int fd = -1;
  if (const ConfinedFolder* folder = confining_folder(file)) {
    auto r = open_confined(file, *folder, flags);
    if (auto* f = std::get_if<ReadFailure>(&r)) return std::move(*f);
    fd = std::get<int>(r);
  } else {
    fd = ::open(file.c_str(), flags);
    if (fd < 0) {
      const int e = errno;
      struct stat st {};
      // (a socket cannot be opened at all: ENXIO, "No such device or address")
      if (::stat(file.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) return not_regular(st.st_mode);
      return ReadFailure{"open", e, errno_message(e)};
    }
  }
  InputFile in(fd, 0);  // (closes fd on every return below but the last)
  struct stat st {};
  if (::fstat(fd, &st) != 0) return ReadFailure{"read", errno, errno_message(errno)};
  if (!S_ISREG(st.st_mode)) return not_regular(st.st_mode);
  const uint64_t size = uint64_t(std::max<off_t>(st.st_size, 0));
  if (size > kind.max_bytes)
    return ReadFailure{"read", EFBIG,
                       fmt::format("is {}, more than the {} anamorph reads as {}", size_text(size),
                                   size_text(kind.max_bytes), kind.what)};
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  if (c && c->record) c->record->insert(confinement_key(file));
  note_read(file, in.fd());  // (for the check that no output overwrites an input: io/read_log.h)
  return InputFile(in.release(), size);
}

std::optional<ReadFailure> read_whole_file(const fs::path& file, std::vector<unsigned char>* out,
                                           const InputKind& kind) {
  out->clear();
  auto opened = open_input(file, kind);
  if (auto* f = std::get_if<ReadFailure>(&opened)) return std::move(*f);
  const InputFile& in = std::get<InputFile>(opened);
  // The size is a hint (a /proc file says 0, a file may grow); the data ends where read(2) says,
  // and never past the kind's limit.
  out->resize(size_t(std::min(in.size(), kind.max_bytes)) + 1);
  size_t got = 0;
  for (;;) {
    if (got == out->size()) {
      if (got > kind.max_bytes)
        return ReadFailure{"read", EFBIG,
                           fmt::format("holds more than the {} anamorph reads as {}",
                                       size_text(kind.max_bytes), kind.what)};
      out->resize(size_t(std::min<uint64_t>(uint64_t(got) * 2 + 4096, kind.max_bytes + 1)));
    }
    const ssize_t n = ::read(in.fd(), out->data() + got, out->size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return ReadFailure{"read", errno, errno_message(errno)};
    if (n == 0) break;
    got += size_t(n);
  }
  out->resize(got);
  return std::nullopt;
}

std::string describe(const ReadFailure& f, const fs::path& file) {
  return fmt::format("cannot {} {}: {}", f.step, file.string(), f.reason);
}

ScopedReadConfinement::ScopedReadConfinement(const ReadConfinement& c)
    : before_(g_confinement), mine_(c) {
  g_confinement = &mine_;
}

ScopedReadConfinement::~ScopedReadConfinement() { g_confinement = before_; }

const ReadConfinement* current_read_confinement() { return g_confinement; }

const ConfinedFolder* confining_folder(const fs::path& file) {
  const ReadConfinement* c = g_confinement;
  if (!c || !c->folder) return nullptr;
  if (c->trusted && c->trusted->count(confinement_key(file))) return nullptr;
  return c->folder;
}

}  // namespace anamorph
