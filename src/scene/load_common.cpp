#include "scene/load_common.h"

#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include <fmt/format.h>

#include "io/image_io.h"
#include "io/read_file.h"
#include "math/user_text.h"
#include "scene/loaders.h"

namespace anamorph {

namespace fs = std::filesystem;

void require_readable(const fs::path& file) {
  std::error_code ec;
  if (fs::is_directory(file, ec))
    throw LoadError("cannot open " + file.string() + ": is a directory");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw LoadError("cannot open " + file.string() + ": " + std::strerror(errno));
}

std::vector<unsigned char> read_file_bytes(const fs::path& file) {
  if (has_nul(file.native())) throw LoadError(nul_in_path_message(file.native()));
  require_readable(file);
  std::vector<unsigned char> bytes;
  if (const auto failure = read_whole_file(file, &bytes))
    throw LoadError(fmt::format("cannot {} {}: {}", failure->step, file.string(),
                                std::strerror(failure->error)));
  return bytes;
}

std::string read_text_file(const fs::path& file) {
  const std::vector<unsigned char> bytes = read_file_bytes(file);
  return std::string(bytes.begin(), bytes.end());
}

std::string lowercase_extension(const fs::path& file) {
  std::string ext = file.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::shared_ptr<const MipMap> ImageFileCache::get(const fs::path& file, bool srgb,
                                                  std::string* error) {
  auto key = std::make_pair(file.lexically_normal().string(), srgb);
  auto it = cache_.find(key);
  if (it == cache_.end()) {
    std::pair<std::shared_ptr<const MipMap>, std::string> entry;
    try {
      entry.first = std::make_shared<const MipMap>(read_image(file, srgb));
    } catch (const std::exception& e) {
      entry.second = e.what();
    }
    it = cache_.emplace(std::move(key), std::move(entry)).first;
  }
  if (!it->second.first) *error = it->second.second;
  return it->second.first;
}

}  // namespace anamorph
