// Shared pieces of the libFuzzer targets: input bytes as a temporary file (the loaders read
// files), and the exception types that count as a clean rejection. Any other exception, a crash,
// a sanitizer report, a hang (-timeout) or a runaway allocation (-rss_limit_mb) is a finding.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace anamorph::fuzz {

// A file holding the input, removed when this goes out of scope.
class TempFile {
 public:
  TempFile(const uint8_t* data, size_t size, const std::string& extension)
      : path_(std::filesystem::temp_directory_path() /
              ("anamorph_fuzz_" + std::to_string(getpid()) + extension)) {
    std::ofstream(path_, std::ios::binary).write(reinterpret_cast<const char*>(data), long(size));
  }
  ~TempFile() {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline std::string text(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

}  // namespace anamorph::fuzz
