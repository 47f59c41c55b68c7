#include "io/temporary_files.h"

#include <unistd.h>

#include <atomic>
#include <climits>
#include <cstring>

namespace anamorph {

namespace {

// Fixed storage: a signal handler may read it at any moment, so nothing here is allocated or
// freed. A slot is free (0), being filled or emptied (1), or holds a name (2).
constexpr int kSlots = 64;
char g_names[kSlots][PATH_MAX];
std::atomic<int> g_state[kSlots];

}  // namespace

int register_temporary(const std::filesystem::path& file) {
  const std::string& name = file.native();
  if (name.size() >= PATH_MAX) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int free = 0;
    if (!g_state[i].compare_exchange_strong(free, 1)) continue;
    std::memcpy(g_names[i], name.c_str(), name.size() + 1);
    g_state[i].store(2);
    return i;
  }
  return -1;
}

void unregister_temporary(int slot) {
  if (slot >= 0 && slot < kSlots) g_state[slot].store(0);
}

void remove_temporaries_now() {
  static_assert(std::atomic<int>::is_always_lock_free, "used from a signal handler");
  for (int i = 0; i < kSlots; ++i)
    if (g_state[i].load() == 2) ::unlink(g_names[i]);
}

}  // namespace anamorph
