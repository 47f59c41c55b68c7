// Which build of anamorph is running, for checkpoints: a render is resumed only by the code that
// began it (another build may draw other numbers or shade differently, and a resumed image would
// mix the two).
#pragma once

#include <string>

namespace anamorph::app {

// A 64-bit hash (hex) of the file this code was loaded from: the program, or the Python module
// it is linked into. Computed once per process (about 3 ms for 10 MB); "unknown" when the file
// cannot be read.
const std::string& build_id();

}  // namespace anamorph::app
