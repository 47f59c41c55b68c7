// Reading a whole file into memory, the one implementation behind image, model and scene reads.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

namespace anamorph {

// Why read_whole_file failed: the step ("open" or "read") and errno (EISDIR for a directory).
struct ReadFailure {
  const char* step;
  int error;
};

// The whole of `file`, read with POSIX calls until its end (so pipes and /proc files work, and a
// read error such as EIO is reported instead of ending the data silently).
std::optional<ReadFailure> read_whole_file(const std::filesystem::path& file,
                                           std::vector<unsigned char>* out);

}  // namespace anamorph
