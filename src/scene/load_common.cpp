#include "scene/load_common.h"

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <iterator>

#include <fmt/format.h>

#include "io/image_io.h"
#include "io/read_file.h"
#include "math/user_text.h"
#include "scene/loaders.h"

namespace anamorph {

namespace fs = std::filesystem;

uint64_t require_readable(const fs::path& file, const InputKind& kind) {
  auto opened = open_input(file, kind);
  if (const auto* f = std::get_if<ReadFailure>(&opened)) throw LoadError(describe(*f, file));
  return std::get<InputFile>(opened).size();
}

std::vector<unsigned char> read_file_bytes(const fs::path& file, const InputKind& kind) {
  if (has_nul(file.native())) throw LoadError(nul_in_path_message(file.native()));
  std::vector<unsigned char> bytes;
  if (const auto failure = read_whole_file(file, &bytes, kind))
    throw LoadError(describe(*failure, file));
  return bytes;
}

std::string read_text_file(const fs::path& file) {
  const std::vector<unsigned char> bytes = read_file_bytes(file, kSceneInput);
  return std::string(bytes.begin(), bytes.end());
}

std::string read_file_part(const fs::path& file, const InputKind& kind, uint64_t offset, size_t max,
                           bool from_end) {
  auto opened = open_input(file, kind);
  if (const auto* f = std::get_if<ReadFailure>(&opened)) throw LoadError(describe(*f, file));
  const InputFile& in = std::get<InputFile>(opened);
  if (from_end) offset = in.size() > offset ? in.size() - offset : 0;
  std::string out(max, '\0');
  size_t got = 0;
  while (got < max) {
    const ssize_t n = ::pread(in.fd(), out.data() + got, max - got, off_t(offset + got));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0)
      throw LoadError(fmt::format("cannot read {}: {}", file.string(), std::strerror(errno)));
    if (n == 0) break;
    got += size_t(n);
  }
  out.resize(got);
  return out;
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
