// No output of a run may be a file the run reads (scene, includes, textures, models and their
// buffers, ray tables, a checkpoint it resumes), nor another output of the same run, nor a
// read-only file, nor a directory. Each command checks its outputs here before it writes
// anything (and before a long load where it can): OutputClash, exit 2, names both roles, e.g.
// "-o scene.png is the scene file this run reads".
//
// Files are the same when they have the same device and inode (symbolic and hard links
// included); outputs that do not exist yet are compared by their resolved paths. Devices,
// FIFOs, sockets and the process's own standard output or error are written directly, never
// replaced, and are not compared (`-o /dev/null --stats /dev/null` is fine).
#pragma once

#include <sys/types.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "io/read_log.h"

namespace anamorph::app {

struct OutputClash : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class OutputGuard {
 public:
  void add_input(const std::filesystem::path& file, const std::string& role);
  void add_inputs(const std::vector<FileRead>& files);
  // `what` names the output as the user gave it: "-o out.png", "the AOVs' EXR out.exr (beside
  // -o out.png)". Throws OutputClash when it may not be written.
  void add_output(const std::filesystem::path& file, const std::string& what);

 private:
  struct Entry {
    std::filesystem::path path;
    std::string what;           // an input's role, an output's description
    std::filesystem::path key;  // resolved path
    dev_t device = 0;
    ino_t inode = 0;  // 0: does not exist (or is not a regular file)
  };
  static Entry entry(const std::filesystem::path& file, std::string what);
  std::vector<Entry> inputs_, outputs_;
};

// A command's check of its outputs (each with its description) against `inputs`: throws
// OutputClash.
void check_outputs(const std::vector<FileRead>& inputs,
                   const std::vector<std::pair<std::filesystem::path, std::string>>& outputs);
// The scene file as the only input known before the load.
std::vector<FileRead> scene_file_input(const std::filesystem::path& scene);

// Whether `file` is written directly rather than replaced: an existing device, FIFO or socket,
// or the file the process's standard output or error is.
bool written_directly(const std::filesystem::path& file);
// Whether `file` is the process's standard output (then messages go to stderr: messages()).
bool is_standard_output(const std::filesystem::path& file);

// Where a command's messages go: stdout, or stderr once an output is stdout itself.
FILE* messages();
void messages_to_stderr();

}  // namespace anamorph::app
