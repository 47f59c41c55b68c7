// The temporary files that exist right now (AtomicFile's, until they are renamed or removed),
// so that a process ended by a signal removes them on its way out and leaves none behind.
#pragma once

#include <filesystem>

namespace anamorph {

// Registers `file`; returns its slot, or -1 when every slot is taken (the file is then left to
// the next write of the same target, which removes temporaries of dead processes).
int register_temporary(const std::filesystem::path& file);
void unregister_temporary(int slot);

// unlink(2) of every registered temporary. Async-signal-safe: for signal handlers.
void remove_temporaries_now();

}  // namespace anamorph
