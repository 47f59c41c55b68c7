// Opening and reading an input file: the one implementation behind every file anamorph reads
// (scenes and includes, images as textures, environments and ray tables, models and their
// buffers, the assimp child's files, Python's load and read_exr, the editor's edits).
//
// An input must be a regular file: a FIFO, a device (/dev/zero, /dev/urandom), a socket or a
// directory is refused with what it is, before anything is read. The open itself never blocks (a
// FIFO with no writer would wait in open(2) forever: it is opened with O_NONBLOCK and refused
// after fstat). A file larger than its kind allows is refused from its size, and a file whose
// size the system does not know (/proc) is read only up to that size.
//
// On a thread where a ReadConfinement is installed (the editor's loads), files are also confined
// to a folder: docs/editor.md, "Security".
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace anamorph {

class ConfinedFolder;

// What an input is: its size limit, and its name in messages ("a scene file").
struct InputKind {
  const char* what;
  uint64_t max_bytes;
};
// Scenes and includes: TOML text, parsed into a tree several times the size of the text.
inline constexpr InputKind kSceneInput{"a scene file", uint64_t(256) << 20};
// Images (textures, environments, ray tables, read_exr): the largest image read is 2^27 pixels of
// float RGBA (2 GiB uncompressed, io_util.h), plus room for layers and headers.
inline constexpr InputKind kImageInput{"an image file", uint64_t(4) << 30};
// Models and their buffers (glTF, OBJ, PLY, ...): a 2-million-triangle OBJ is 60 MB.
inline constexpr InputKind kModelInput{"a model file", uint64_t(4) << 30};
// Anything else a user points anamorph at (developers' page folder, documentation).
inline constexpr InputKind kTextInput{"a text file", uint64_t(64) << 20};

// Why an input could not be opened or read: the step ("open" or "read") and the reason in words
// ("is a FIFO, not a regular file", "No such file or directory"). `error` is errno when the
// system said it, else 0.
struct ReadFailure {
  const char* step;
  int error;
  std::string reason;
};

// An input opened for reading (closed with this object).
class InputFile {
 public:
  InputFile(int fd, uint64_t size) : fd_(fd), size_(size) {}
  ~InputFile();
  InputFile(InputFile&& o) noexcept : fd_(std::exchange(o.fd_, -1)), size_(o.size_) {}
  InputFile& operator=(InputFile&&) = delete;
  InputFile(const InputFile&) = delete;
  int fd() const { return fd_; }
  int release() { return std::exchange(fd_, -1); }
  uint64_t size() const { return size_; }  // from fstat (0 for /proc files)

 private:
  int fd_;
  uint64_t size_;
};

// Opens `file` as an input of `kind` (the rules above).
std::variant<InputFile, ReadFailure> open_input(const std::filesystem::path& file,
                                                const InputKind& kind);

// The whole of `file`, read with POSIX calls until its end (a read error such as EIO is
// reported, not taken for the end of the data), at most kind.max_bytes.
std::optional<ReadFailure> read_whole_file(const std::filesystem::path& file,
                                           std::vector<unsigned char>* out, const InputKind& kind);

// "cannot open FILE: REASON": the failure in the words every reader uses.
std::string describe(const ReadFailure& f, const std::filesystem::path& file);

// The editor's rule for the files one of its loads may read (installed on the loading thread by
// ScopedReadConfinement): a file in `trusted` (absolute, lexically normal) is opened as the
// command line opens it (the files the scene read when the server started, which the user chose);
// any other only beneath `folder`, through its descriptor, with no symbolic link on the way.
// With `folder` null nothing is confined, and with `record` set every file opened is added to it.
struct ReadConfinement {
  const ConfinedFolder* folder = nullptr;
  const std::set<std::string>* trusted = nullptr;
  std::set<std::string>* record = nullptr;
};

// Installs `c` on this thread for its lifetime (the one before comes back after).
class ScopedReadConfinement {
 public:
  explicit ScopedReadConfinement(const ReadConfinement& c);
  ~ScopedReadConfinement();
  ScopedReadConfinement(const ScopedReadConfinement&) = delete;
  ScopedReadConfinement& operator=(const ScopedReadConfinement&) = delete;

 private:
  const ReadConfinement* before_;
  ReadConfinement mine_;
};

// The confinement installed on this thread, or null.
const ReadConfinement* current_read_confinement();
// The folder a read of `file` on this thread is confined to (none: read as the command line
// reads it).
const ConfinedFolder* confining_folder(const std::filesystem::path& file);

// A file's kind in words, for a file that is not regular: "a FIFO", "a character device", ...
const char* file_kind_name(unsigned mode);

}  // namespace anamorph
