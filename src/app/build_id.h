// Which build of anamorph is running, for checkpoints: a render is resumed only by the code that
// began it (another build may draw other numbers or shade differently, and a resumed image would
// mix the two).
#pragma once

#include <string>

namespace anamorph::app {

// The GNU build ID (hex: the linker's hash of the code) of the object this code is linked into,
// the program or the Python module; without one, a 64-bit hash of that object's file
// ("HASH-SIZE"); "unknown" when neither can be had. Computed once per process.
const std::string& build_id();

}  // namespace anamorph::app
