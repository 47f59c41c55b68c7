// All emitters of a scene behind one sampling interface: point, spot and directional lights
// (delta), emissive triangles (quad lights become two of them), emissive spheres, and the
// environment (importance-sampled by luminance when it is an image). The path tracer picks the
// light of a shading point in two steps, each by what a light can give that point: among the
// lights at infinity (directional, environment) and the finite ones as a group, then within the
// group by the light tree (render/light_tree.h).
#pragma once

#include <unordered_map>
#include <vector>

#include "accel/accel.h"
#include "math/distribution.h"
#include "render/light_tree.h"
#include "scene/scene.h"

namespace anamorph {

struct LightSample {
  Color L;             // incident radiance (or intensity / d^2 for point-like lights)
  Vec3 wi;             // unit direction toward the light
  double dist = kInf;  // distance to the sampled point (kInf for directional / environment)
  double pdf = 0;      // solid-angle density (1 for delta lights), not including the pick pmf
  bool delta = false;
};

class Lights {
 public:
  Lights(const Scene& scene, const Accel& accel);

  size_t count() const { return emitters_.size(); }
  // Chooses the light *index to sample from point p with shading normal n, with probability
  // *pmf; false when no light can reach p.
  bool pick(double u, const Vec3& p, const Vec3& n, size_t* index, double* pmf) const;
  // The probability that pick() at (p, n) chooses light i.
  double pick_pmf(size_t i, const Vec3& p, const Vec3& n) const;
  // A direction toward light i from p, whose shading normal is n: a constant environment is
  // sampled cosine-weighted about n (no sample below the shading hemisphere; directions there
  // are left to BSDF sampling, whose MIS weight becomes 1).
  bool sample(size_t i, const Vec3& p, const Vec3& n, Vec2 u, LightSample* out) const {
    return sample_from(i, p, &n, u, out);
  }
  // The same for a point without a normal (Whitted's): a constant environment is sampled
  // uniformly over the sphere.
  bool sample(size_t i, const Vec3& p, Vec2 u, LightSample* out) const {
    return sample_from(i, p, nullptr, u, out);
  }
  // Whitted shades every delta light and one power-chosen area emitter.
  const std::vector<uint32_t>& delta_lights() const { return delta_; }
  bool has_area() const { return area_pick_.size() > 0 && area_pick_.total() > 0; }
  size_t pick_area(double u, double* pmf) const {
    return area_[area_pick_.sample_discrete(u, pmf)];
  }

  // Radiance leaving an emissive surface at a hit toward wo (zero if not emissive).
  Color emitted(const Hit& h, const Vec3& wo) const;
  // Density (solid angle, pick pmf included) with which light sampling at `from` (shading
  // normal from_n) would have produced direction wi reaching the emitter at `h` (for MIS).
  double pdf_emitter(const Hit& h, const Vec3& from, const Vec3& from_n, const Vec3& wi) const;

  Color environment(const Vec3& dir) const;
  bool has_environment() const { return env_index_ >= 0; }
  // Pick pmf included; p, n: the point the ray left and its shading normal (as for sample()).
  double pdf_environment(const Vec3& dir, const Vec3& p, const Vec3& n) const;
  // Mean radiance of the environment over the sphere (Whitted's ambient term).
  Color environment_average() const { return env_average_; }

 private:
  struct Emitter {
    enum class Kind { Point, Spot, Directional, Triangle, Sphere, Environment } kind;
    Color L;                              // intensity / irradiance / radiance (constant part)
    Vec3 p0, p1, p2;                      // triangle vertices; p0 = position / sphere center
    Vec2 uv0, uv1, uv2;                   // triangle uvs (textured emission)
    Vec3 dir;                             // spot axis / directional travel direction
    double cos_inner = 1, cos_outer = 1;  // spot
    Light::SpotFalloff falloff = Light::SpotFalloff::Smoothstep;
    double cycles_band = 0;  // spot, Cycles' falloff: the blend band in the cosine
    double range = 0;        // point, spot: 0 unlimited
    double radius = 0, area = 0;
    const Material* material = nullptr;  // triangles and spheres: emission texture
    bool two_sided = true;
  };
  struct Key {
    uint32_t object, mesh, prim;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return std::hash<uint64_t>()((uint64_t(k.object) << 32 | k.mesh) * 0x9E3779B97F4A7C15ULL ^
                                   k.prim);
    }
  };

  // The constructor's steps: each adds emitters and their powers.
  void add_punctual(const Light& l, std::vector<double>& power);
  void add_emissive_mesh(uint32_t id, const TriangleMesh& m, const Transform* xf,
                         uint32_t mesh_index, std::vector<double>& power);
  void add_emissive_sphere(uint32_t id, const Accel::Record& rec, std::vector<double>& power);
  void add_environment(std::vector<double>& power);
  // The two-step choice of pick(): the groups and the tree.
  void build_pick(const std::vector<double>& power);
  // What group g can give p (the tree's root importance; 4 pi E |cos| for a directional light
  // of irradiance E, as the tree weighs a point light; 4 pi pi L for an environment image of
  // mean radiance L, a quarter of it for a constant one), and all groups' sum.
  double group_weight(size_t g, const Vec3& p, const Vec3& n) const;
  double group_total(const Vec3& p, const Vec3& n) const;
  LightBounds bounds_of(const Emitter& e, double power) const;
  // sample()'s cases.
  static bool sample_punctual(const Emitter& e, const Vec3& p, LightSample* out);
  bool sample_triangle(const Emitter& e, const Vec3& p, Vec2 u, LightSample* out) const;
  static bool sample_sphere(const Emitter& e, const Vec3& p, Vec2 u, LightSample* out);
  // n: the shading normal at p, or null.
  bool sample_from(size_t i, const Vec3& p, const Vec3* n, Vec2 u, LightSample* out) const;
  bool sample_environment(const Vec3* n, Vec2 u, LightSample* out) const;
  Color emission_at(const Emitter& e, Vec2 uv) const;
  // A point or spot light's factor toward -wi beyond its intensity / distance^2: the spot's
  // cone and the range's window.
  static double punctual_factor(const Emitter& e, const Vec3& wi, double dist);
  Vec2 env_uv(const Vec3& d) const;
  Vec3 env_dir(Vec2 uv) const;

  const Scene& scene_;
  std::vector<Emitter> emitters_;
  std::unordered_map<Key, uint32_t, KeyHash> by_surface_;
  static constexpr uint32_t kInTree = ~0u;
  std::vector<uint32_t> group_emitter_;  // each group's emitter, kInTree for the tree's
  std::vector<uint32_t> group_of_;       // each emitter's group
  LightTree tree_;
  std::vector<uint32_t> tree_emitter_, tree_slot_;  // tree index -> emitter, and back
  Distribution1D area_pick_;
  std::vector<uint32_t> delta_, area_;
  int env_index_ = -1;
  Color env_average_;
  double env_luminance_ = 0;  // the environment's mean luminance over the sphere (group weight)
  Distribution2D env_dist_;
  double scene_radius_ = 1;
  Vec3 scene_center_;
};

}  // namespace anamorph
