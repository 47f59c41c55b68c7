// Cheap checks of a model file's declared sizes before a third-party parser sees it, so a tiny
// file that claims billions of elements gets a clear error instead of a huge allocation.
#pragma once

#include <filesystem>

namespace anamorph {

// For a PLY file: every element count in the header, times the smallest encoding of one element,
// fits in the file, and the header ends. Throws LoadError otherwise; returns quietly for files
// that do not start with "ply".
void check_ply_counts(const std::filesystem::path& file);

}  // namespace anamorph
