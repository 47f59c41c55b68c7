#include "scene/load_validate.h"

#include <fmt/format.h>

#include <sstream>

#include "scene/load_common.h"
#include "scene/loaders.h"

namespace anamorph {

namespace {

// Bytes one value of a PLY property type takes at least: its size in binary files, a digit and a
// separator in ASCII ones.
uint64_t min_value_bytes(const std::string& type, bool ascii) {
  if (ascii) return 2;
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "double" || type == "float64") return 8;
  return 4;  // int, uint, float and their sized names
}

}  // namespace

void check_ply_counts(const std::filesystem::path& file) {
  const uint64_t size = require_readable(file, kModelInput);
  // The header: at most 10,000 lines, read from the first megabytes.
  std::istringstream in(read_file_part(file, kModelInput, 0, size_t(4) << 20));
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) return;  // not PLY
  bool ascii = true;
  // Every element's count times its smallest encoding must fit in the file: a 200-byte file
  // that declares two billion vertices is rejected before anything is allocated for them.
  uint64_t need = 0;
  std::string element;
  uint64_t count = 0, per_element = 0;
  const auto close_element = [&] {
    if (!element.empty() && count > 0 && per_element > 0) {
      if (count > size / per_element || need + count * per_element > size)
        throw LoadError(fmt::format(
            "the PLY header declares {} {} elements, more than the file's {} bytes can hold", count,
            element, size));
      need += count * per_element;
    }
  };
  for (int lines = 0; std::getline(in, line) && lines < 10000; ++lines) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "format") {
      std::string f;
      words >> f;
      ascii = f == "ascii";
    } else if (word == "element") {
      close_element();
      element.clear(), count = 0, per_element = 0;
      words >> element >> count;
    } else if (word == "property") {
      std::string type;
      words >> type;
      if (type == "list") words >> type;  // at least its length (the list may be empty)
      per_element += min_value_bytes(type, ascii);
    } else if (word == "end_header") {
      close_element();
      return;
    }
  }
  // (assimp 5.2.5 loops forever on such a file.)
  throw LoadError("the PLY header has no end_header line");
}

}  // namespace anamorph
