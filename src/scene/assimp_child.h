// The part of the assimp loader that runs in the isolated process (scene/isolated.h): assimp
// reads and post-processes the file there, and hands the result back as bytes.
#pragma once

#include <filesystem>
#include <vector>

namespace anamorph {

// assimp's binary dump (assbin) of the post-processed file, then the mesh names (the dump drops
// them), then the files assimp opened (the model, an OBJ's material library): each a list of
// NUL-terminated strings followed by its byte count (8 bytes). Throws LoadError with assimp's
// message, or std::bad_alloc when assimp ran out of memory.
std::vector<unsigned char> assimp_answer(const std::filesystem::path& file);

}  // namespace anamorph
