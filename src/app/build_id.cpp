#include "app/build_id.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

#include "math/rng.h"

namespace anamorph::app {

namespace {

// Every byte of the file, eight at a time through a 64-bit mixer.
std::string hash_of_file(const char* path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return "";
  std::vector<char> buf(size_t(1) << 20);
  uint64_t h = 0x9e3779b97f4a7c15ULL, size = 0;
  while (f) {
    f.read(buf.data(), std::streamsize(buf.size()));
    const size_t n = size_t(f.gcount());
    for (size_t i = 0; i < n; i += 8) {
      uint64_t w = 0;
      std::memcpy(&w, buf.data() + i, std::min<size_t>(8, n - i));
      h = mix64(h ^ w) + i;
    }
    size += n;
  }
  return fmt::format("{:016x}-{}", mix64(h ^ size), size);
}

}  // namespace

const std::string& build_id() {
  static const std::string id = [] {
    Dl_info info{};
    std::string h;
    if (::dladdr(reinterpret_cast<void*>(&build_id), &info) && info.dli_fname)
      h = hash_of_file(info.dli_fname);
    if (h.empty()) h = hash_of_file("/proc/self/exe");
    return h.empty() ? std::string("unknown") : h;
  }();
  return id;
}

}  // namespace anamorph::app
