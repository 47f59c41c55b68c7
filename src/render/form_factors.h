// Form factors measured with a virtual camera (the paper's future work: "virtual cameras might
// be considered for the form factor calculations of non-polygonal objects with the radiosity
// method"). At points spread over a source object by area, a hemispherical camera around the
// surface normal whose pixels have equal projected solid angle (the orthographic fisheye,
// Nusselt's analog) traces into the scene; the fraction of its rays that first hit object j is
// the point-to-object form factor, and its area-weighted mean over the source is F_ij. Works
// for analytic shapes and meshes alike: nothing is tessellated.
#pragma once

#include <atomic>
#include <string>
#include <string_view>
#include <vector>

#include "accel/accel.h"
#include "scene/scene.h"

namespace anamorph {

// The ranges of the counts below that the CLI (anamorph formfactors) and Python accept.
inline constexpr int kMaxFormFactorOrigins = 1 << 24, kMaxFormFactorRays = 1 << 20,
                     kMaxFormFactorPathDepth = 10000;

struct FormFactorOptions {
  int origins = 2048;                // points per source object (stratified by area)
  int rays = 256;                    // hemisphere camera samples per point (a 16 x 16 image)
  uint64_t seed = 0;                 // the same seed, the same numbers
  std::vector<std::string> sources;  // objects whose rows to measure (empty: every one with area)
  std::vector<std::string> inward;   // objects whose surfaces face inward (enclosures)
  const std::atomic<bool>* cancel = nullptr;
};

// The name of the column of rays that hit nothing: no object is listed under it.
inline constexpr std::string_view kEnvironmentColumn = "environment";

struct FormFactors {
  // Every top-level object of the scene (receivers), by unique name (a repeated name gets "#2",
  // "#3", ...; kEnvironmentColumn counts as taken); column names.size() of F is the environment
  // (rays that hit nothing).
  std::vector<std::string> names;
  std::vector<double> areas;                  // world area per object (0 where infinite)
  std::vector<int> rows;                      // the object index of each measured row
  std::vector<std::vector<double>> F, error;  // [row][column]: estimate, standard error
  // Per object, why it has no row when all rows were asked for (an infinite plane; an area
  // beyond double precision); empty for the others.
  std::vector<std::string> no_row;
  std::vector<std::string> notes;  // for the user: a name changed to keep names unique
  // Reciprocity A_i F_ij = A_j F_ji over measured pairs: the largest |difference| in standard
  // errors of the difference, and the pair.
  double worst_reciprocity_z = 0;
  int worst_i = -1, worst_j = -1;
};

// The objects' unique names, as FormFactors::names; `notes` gets a line for each name changed
// from the scene's.
std::vector<std::string> form_factor_names(const Accel& accel, std::vector<std::string>* notes);

// Throws std::invalid_argument naming an unknown object, or a requested source without area
// (and why).
FormFactors measure_form_factors(const Accel& accel, const FormFactorOptions& o);

// The path tracer's mean outgoing radiance over each measured object's surface (Le + rho times
// the mean incoming radiance over cosine-distributed directions), with standard errors: the
// check of the radiosity solution (B / pi) by an independent method.
struct PathRadiance {
  std::vector<Color> mean, error;
};
PathRadiance path_traced_radiance(const Scene& scene, const Accel& accel, const FormFactors& f,
                                  const FormFactorOptions& o, int max_depth);

}  // namespace anamorph
