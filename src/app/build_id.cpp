#include "app/build_id.h"

#include <dlfcn.h>
#include <elf.h>
#include <fmt/format.h>
#include <link.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

#include "math/rng.h"

namespace anamorph::app {

namespace {

// The linker's GNU build ID (a hash of the linked code) of the loaded object holding `addr`;
// empty when it has none.
std::string gnu_build_id(const void* addr) {
  struct Search {
    uintptr_t addr;
    std::string id;
  } s{reinterpret_cast<uintptr_t>(addr), {}};
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* data) {
        auto& found = *static_cast<Search*>(data);
        bool holds = false;
        for (int i = 0; i < info->dlpi_phnum; ++i) {
          const ElfW(Phdr)& p = info->dlpi_phdr[i];
          const uintptr_t lo = info->dlpi_addr + p.p_vaddr;
          if (p.p_type == PT_LOAD && found.addr >= lo && found.addr < lo + p.p_memsz) holds = true;
        }
        if (!holds) return 0;
        for (int i = 0; i < info->dlpi_phnum; ++i) {
          const ElfW(Phdr)& p = info->dlpi_phdr[i];
          if (p.p_type != PT_NOTE) continue;
          const char* n = reinterpret_cast<const char*>(info->dlpi_addr + p.p_vaddr);
          const char* end = n + p.p_memsz;
          while (n + sizeof(ElfW(Nhdr)) <= end) {
            const auto* h = reinterpret_cast<const ElfW(Nhdr)*>(n);
            const char* name = n + sizeof(ElfW(Nhdr));
            const char* desc = name + ((h->n_namesz + 3) & ~3u);
            if (h->n_type == NT_GNU_BUILD_ID && h->n_namesz == 4 &&
                std::memcmp(name, "GNU", 4) == 0 && desc + h->n_descsz <= end)
              for (unsigned k = 0; k < h->n_descsz; ++k)
                found.id += fmt::format("{:02x}", static_cast<unsigned char>(desc[k]));
            n = desc + ((h->n_descsz + 3) & ~3u);
          }
        }
        return 1;
      },
      &s);
  return s.id;
}

// Every byte of the file, eight at a time through a 64-bit mixer (without a build ID).
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
    std::string h = gnu_build_id(reinterpret_cast<const void*>(&build_id));
    Dl_info info{};
    if (h.empty() && ::dladdr(reinterpret_cast<void*>(&build_id), &info) && info.dli_fname)
      h = hash_of_file(info.dli_fname);
    if (h.empty()) h = hash_of_file("/proc/self/exe");
    return h.empty() ? std::string("unknown") : h;
  }();
  return id;
}

}  // namespace anamorph::app
