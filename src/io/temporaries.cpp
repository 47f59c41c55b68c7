// The temporaries that atomic writes go through (AtomicFile, ConfinedFolder::write_atomic): their
// names, and the removal of those a killed process left behind.
#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include <fmt/format.h>

#include "io/io_util.h"

namespace anamorph {

namespace io_detail {

std::string temporary_name(const std::string& name, uint64_t random) {
  return fmt::format(".{}.tmp-{}-{:016x}", name, ::getpid(), random);
}

void remove_stale_temporaries_at(int dirfd, const std::string& name) {
  const std::string prefix = "." + name + ".tmp-";
  const int own = ::fcntl(dirfd, F_DUPFD_CLOEXEC, 0);  // (closedir closes its descriptor)
  DIR* d = own >= 0 ? ::fdopendir(own) : nullptr;
  if (!d) {
    if (own >= 0) ::close(own);
    return;
  }
  ::rewinddir(d);
  while (const dirent* e = ::readdir(d)) {
    const std::string entry = e->d_name;
    if (entry.rfind(prefix, 0) != 0) continue;
    char* end = nullptr;
    const long pid = std::strtol(entry.c_str() + prefix.size(), &end, 10);
    if (pid <= 0 || !end || *end != '-' || pid == ::getpid()) continue;
    if (::kill(pid_t(pid), 0) != 0 && errno == ESRCH) ::unlinkat(dirfd, e->d_name, 0);
  }
  ::closedir(d);
}

}  // namespace io_detail

}  // namespace anamorph
