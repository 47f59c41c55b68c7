// Checks and repairs shared by the glTF and assimp loaders. Every mesh passes check_mesh before
// it is kept, so the renderer can trust its positions, indices, normals and uvs.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "model/mesh.h"

namespace anamorph {

// What check_mesh repaired, summed over a file so that each kind gives one warning.
struct MeshRepairs {
  size_t degenerate_triangles = 0;  // zero-area triangles, dropped
  size_t bad_normals = 0;           // zero-length or non-finite normals, recomputed
  size_t bad_uvs = 0;               // non-finite uvs, set to (0, 0)
};

// Throws LoadError("mesh '<name>': ...") without the file name (the loader adds it) when
// positions are non-finite, an index is out of range, or attribute arrays do not match the
// positions. Drops zero-area triangles, recomputes bad normals from the geometry (area-weighted
// face normals around the vertex), normalizes the others, zeroes non-finite uvs.
void check_mesh(TriangleMesh& mesh, MeshRepairs& repairs);

// Smooth vertex normals for a mesh that has none: area-weighted face normals of the faces around
// each position, but only of faces within `crease_degrees` of the corner's own face, so hard
// edges (a cube's 90 degrees) stay hard. Vertices are split where a corner needs its own normal.
void generate_normals(TriangleMesh& mesh, double crease_degrees);

// One warning per kind of repair, naming the file and the count.
void add_repair_warnings(const MeshRepairs& repairs, const std::string& file,
                         std::vector<std::string>& warnings);

}  // namespace anamorph
