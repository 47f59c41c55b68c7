#include "scene/gltf_rig_reader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "scene/gltf_animation.h"
#include "scene/load_gltf_accessor.h"
#include "scene/loaders.h"

namespace anamorph {

namespace {

std::vector<Vec3f> to_vec3(const std::vector<float>& f) {
  std::vector<Vec3f> v(f.size() / 3);
  for (size_t i = 0; i < v.size(); ++i) v[i] = {f[3 * i], f[3 * i + 1], f[3 * i + 2]};
  return v;
}

bool all_finite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

RigNode rig_node(const tinygltf::Node& n, const tinygltf::Model& m) {
  RigNode r;
  if (n.matrix.size() == 16) {
    r.has_matrix = true;
    for (int row = 0; row < 4; ++row)
      for (int c = 0; c < 4; ++c) r.matrix.m[row][c] = n.matrix[size_t(c * 4 + row)];
  }
  if (n.translation.size() == 3) r.trs.t = {n.translation[0], n.translation[1], n.translation[2]};
  if (n.rotation.size() == 4)
    r.trs.r = normalized({n.rotation[0], n.rotation[1], n.rotation[2], n.rotation[3]});
  if (n.scale.size() == 3) r.trs.s = {n.scale[0], n.scale[1], n.scale[2]};
  if (!n.weights.empty())
    r.weights = n.weights;
  else if (n.mesh >= 0 && size_t(n.mesh) < m.meshes.size())
    r.weights = m.meshes[size_t(n.mesh)].weights;
  return r;
}

// Parents before children, over every node (roots in index order, then depth first).
std::vector<int> parent_first(const std::vector<RigNode>& nodes, const tinygltf::Model& m) {
  std::vector<int> order;
  order.reserve(nodes.size());
  std::vector<int> stack;
  for (size_t i = nodes.size(); i-- > 0;)
    if (nodes[i].parent < 0) stack.push_back(int(i));
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    order.push_back(i);
    const auto& children = m.nodes[size_t(i)].children;
    for (auto c = children.rbegin(); c != children.rend(); ++c) stack.push_back(*c);
  }
  return order;
}

// How many numbers per key a channel's sampler must give, and its path; false for a path we
// do not animate.
bool channel_path(const std::string& path, AnimPath* p) {
  static const std::map<std::string, AnimPath> kPaths = {{"translation", AnimPath::Translation},
                                                         {"rotation", AnimPath::Rotation},
                                                         {"scale", AnimPath::Scale},
                                                         {"weights", AnimPath::Weights}};
  const auto it = kPaths.find(path);
  if (it == kPaths.end()) return false;
  *p = it->second;
  return true;
}

class AnimationReader {
 public:
  AnimationReader(const tinygltf::Model& m, GltfRig& rig, std::vector<std::string>& warnings)
      : m_(m), rig_(rig), warnings_(warnings) {}

  void read(size_t a) {
    const tinygltf::Animation& anim = m_.animations[a];
    const std::string name = anim.name.empty() ? fmt::format("animation {}", a) : anim.name;
    rig_.animations.push_back(name);
    std::map<int, uint32_t> sampler_index;  // (per path width: a sampler serves one path)
    for (size_t c = 0; c < anim.channels.size(); ++c) {
      const tinygltf::AnimationChannel& ch = anim.channels[c];
      const std::string where = fmt::format("animation '{}' channel {}", name, c);
      AnimPath path;
      if (ch.target_node < 0 || size_t(ch.target_node) >= rig_.nodes.size()) {
        warn(where, fmt::format("targets node {}, which does not exist", ch.target_node));
        continue;
      }
      if (!channel_path(ch.target_path, &path)) {
        warn(where, fmt::format("animates '{}', which is not read", ch.target_path));
        continue;
      }
      if (path != AnimPath::Weights && rig_.nodes[size_t(ch.target_node)].has_matrix) {
        warn(where, fmt::format("animates node {}, which is given by a matrix (glTF allows "
                                "animating only nodes given by translation, rotation, scale)",
                                ch.target_node));
        continue;
      }
      if (ch.sampler < 0 || size_t(ch.sampler) >= anim.samplers.size()) {
        warn(where, fmt::format("sampler {} does not exist", ch.sampler));
        continue;
      }
      const int width = path == AnimPath::Rotation ? 4 : path == AnimPath::Weights ? 0 : 3;
      const auto key = ch.sampler * 8 + width;
      auto it = sampler_index.find(key);
      if (it == sampler_index.end()) {
        AnimSampler s;
        if (!read_sampler(anim.samplers[size_t(ch.sampler)], width, where, &s)) continue;
        rig_.samplers.push_back(std::move(s));
        it = sampler_index.emplace(key, uint32_t(rig_.samplers.size() - 1)).first;
      }
      rig_.channels.push_back({ch.target_node, path, it->second, uint32_t(a)});
    }
  }

 private:
  void warn(const std::string& where, const std::string& what) {
    warnings_.push_back(fmt::format("{} {}; it is ignored", where, what));
  }

  // `width` 0: weights, as many per key as the output holds.
  bool read_sampler(const tinygltf::AnimationSampler& gs, int width, const std::string& where,
                    AnimSampler* s) {
    if (gs.interpolation == "LINEAR")
      s->interp = Interpolation::Linear;
    else if (gs.interpolation == "STEP")
      s->interp = Interpolation::Step;
    else if (gs.interpolation == "CUBICSPLINE")
      s->interp = Interpolation::CubicSpline;
    else {
      warn(where,
           fmt::format("has interpolation '{}' (LINEAR, STEP or CUBICSPLINE)", gs.interpolation));
      return false;
    }
    try {
      const std::vector<float> t = read_accessor_floats(m_, gs.input, 1);
      s->times.assign(t.begin(), t.end());
      const int comps = width == 0 ? 1 : width;
      const std::vector<float> v = read_accessor_floats(m_, gs.output, comps);
      s->values.assign(v.begin(), v.end());
    } catch (const LoadError& e) {
      warn(where, e.what());
      return false;
    }
    const size_t keys = s->times.size();
    const size_t per_key = s->interp == Interpolation::CubicSpline ? 3 : 1;
    if (keys == 0) {
      warn(where, "has no keys");
      return false;
    }
    if (!all_finite(s->times) || !std::is_sorted(s->times.begin(), s->times.end())) {
      warn(where, "has key times that are not finite or go backwards");
      return false;
    }
    if (!all_finite(s->values)) {
      warn(where, "has values that are not finite");
      return false;
    }
    if (width == 0) {
      if (s->values.size() % (keys * per_key) != 0 || s->values.empty()) {
        warn(where, fmt::format("has {} weights for {} keys", s->values.size(), keys));
        return false;
      }
      s->width = int(s->values.size() / (keys * per_key));
    } else {
      s->width = width;
      if (s->values.size() != keys * per_key * size_t(width)) {
        warn(where,
             fmt::format("has {} values for {} keys of {} numbers{}",
                         s->values.size() / size_t(width), keys, width,
                         per_key == 3 ? " (CUBICSPLINE: in-tangent, value, out-tangent)" : ""));
        return false;
      }
    }
    return true;
  }

  const tinygltf::Model& m_;
  GltfRig& rig_;
  std::vector<std::string>& warnings_;
};

Skin read_skin(const tinygltf::Model& m, size_t index, std::vector<std::string>& warnings) {
  const tinygltf::Skin& gs = m.skins[index];
  Skin s;
  s.name = gs.name.empty() ? fmt::format("skin {}", index) : gs.name;
  for (const int j : gs.joints)
    if (j < 0 || size_t(j) >= m.nodes.size())
      throw LoadError(fmt::format("skin '{}': joint node {} does not exist ({} nodes)", s.name, j,
                                  m.nodes.size()));
  s.joints = gs.joints;
  s.inverse_bind.assign(s.joints.size(), Mat4::identity());
  if (gs.inverseBindMatrices < 0) return s;
  std::vector<float> f;
  try {
    f = read_accessor_floats(m, gs.inverseBindMatrices, 16);
  } catch (const LoadError& e) {
    throw LoadError(fmt::format("skin '{}' inverseBindMatrices: {}", s.name, e.what()));
  }
  if (f.size() / 16 < s.joints.size())
    throw LoadError(fmt::format("skin '{}': {} inverse bind matrices for {} joints", s.name,
                                f.size() / 16, s.joints.size()));
  bool finite = true;
  for (size_t j = 0; j < s.joints.size(); ++j)
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) {
        const double x = f[j * 16 + size_t(c * 4 + r)];
        finite = finite && std::isfinite(x);
        s.inverse_bind[j].m[r][c] = x;
      }
  if (!finite) {
    warnings.push_back(fmt::format(
        "skin '{}': inverse bind matrices that are not finite; identity used instead", s.name));
    s.inverse_bind.assign(s.joints.size(), Mat4::identity());
  }
  return s;
}

}  // namespace

GltfRig read_rig(const tinygltf::Model& m, std::vector<std::string>& warnings) {
  GltfRig rig;
  rig.nodes.reserve(m.nodes.size());
  for (const auto& n : m.nodes) rig.nodes.push_back(rig_node(n, m));
  for (size_t p = 0; p < m.nodes.size(); ++p)
    for (const int c : m.nodes[p].children) rig.nodes[size_t(c)].parent = int(p);
  rig.order = parent_first(rig.nodes, m);
  AnimationReader reader(m, rig, warnings);
  for (size_t a = 0; a < m.animations.size(); ++a) reader.read(a);
  for (size_t s = 0; s < m.skins.size(); ++s) rig.skins.push_back(read_skin(m, s, warnings));
  return rig;
}

namespace {

// JOINTS_k / WEIGHTS_k sets as flat arrays of 4 per vertex each.
void read_influences(const tinygltf::Model& m, const tinygltf::Primitive& pr, const Skin& skin,
                     size_t vertices, Deformer::Part& part, std::vector<std::string>& warnings) {
  std::vector<std::vector<float>> js, ws;
  for (int set = 0; set < 2; ++set) {
    const auto j = pr.attributes.find(fmt::format("JOINTS_{}", set));
    const auto w = pr.attributes.find(fmt::format("WEIGHTS_{}", set));
    if (j == pr.attributes.end() || w == pr.attributes.end()) break;
    js.push_back(read_accessor_floats(m, j->second, 4));
    ws.push_back(read_accessor_floats(m, w->second, 4));
    if (js.back().size() != vertices * 4 || ws.back().size() != vertices * 4)
      throw LoadError(fmt::format("JOINTS_{} / WEIGHTS_{} have {} / {} elements, POSITION has {}",
                                  set, set, js.back().size() / 4, ws.back().size() / 4, vertices));
  }
  part.influences = int(js.size() * 4);
  part.joints.assign(vertices * size_t(part.influences), 0);
  part.weights.assign(vertices * size_t(part.influences), 0.0f);
  size_t bad = 0;
  for (size_t v = 0; v < vertices; ++v) {
    double sum = 0;
    for (int k = 0; k < part.influences; ++k) {
      const size_t set = size_t(k / 4), c = size_t(k % 4);
      const double joint = js[set][v * 4 + c], weight = ws[set][v * 4 + c];
      if (!(weight > 0)) continue;
      if (!(joint >= 0 && joint < double(skin.joints.size()))) {
        ++bad;
        continue;
      }
      const size_t at = v * size_t(part.influences) + size_t(k);
      part.joints[at] = uint16_t(joint);
      part.weights[at] = float(weight);
      sum += weight;
    }
    if (sum > 0 && std::isfinite(sum))
      for (int k = 0; k < part.influences; ++k)
        part.weights[v * size_t(part.influences) + size_t(k)] /= float(sum);
  }
  if (bad > 0)
    warnings.push_back(
        fmt::format("skin '{}': {} vertex influence(s) name a joint the skin does "
                    "not have ({} joints); they are ignored",
                    skin.name, bad, skin.joints.size()));
}

}  // namespace

Deformer::Part read_deformer_part(const tinygltf::Model& m, const tinygltf::Primitive& pr,
                                  const std::vector<Vec3f>& repaired_normals, const Skin* skin,
                                  std::vector<std::string>& warnings) {
  Deformer::Part part;
  part.positions = to_vec3(read_accessor_floats(m, pr.attributes.at("POSITION"), 3));
  const size_t n = part.positions.size();
  if (const auto it = pr.attributes.find("NORMAL");
      it != pr.attributes.end() && repaired_normals.size() == n) {
    part.normals = to_vec3(read_accessor_floats(m, it->second, 3));
    for (size_t i = 0; i < n; ++i) {
      const Vec3 v(part.normals[i]);
      const double len = length(v);
      part.normals[i] = len > 0 && std::isfinite(len) ? Vec3f(v / len) : repaired_normals[i];
    }
  }
  for (size_t t = 0; t < pr.targets.size(); ++t) {
    auto read = [&](const char* key, bool wanted) {
      const auto it = pr.targets[t].find(key);
      if (!wanted || it == pr.targets[t].end()) return std::vector<Vec3f>{};
      std::vector<Vec3f> d = to_vec3(read_accessor_floats(m, it->second, 3));
      if (d.size() != n)
        throw LoadError(
            fmt::format("morph target {} {} has {} elements, base has {}", t, key, d.size(), n));
      return d;
    };
    part.target_positions.push_back(read("POSITION", true));
    part.target_normals.push_back(read("NORMAL", !part.normals.empty()));
  }
  if (skin) read_influences(m, pr, *skin, n, part, warnings);
  return part;
}

void finish_rig(GltfRig& rig) {
  rig.moving.assign(rig.nodes.size(), false);
  std::vector<bool> animated(rig.nodes.size(), false);
  bool first = true;
  for (const AnimChannel& c : rig.channels) {
    if (c.path != AnimPath::Weights) animated[size_t(c.node)] = true;
    const AnimSampler& s = rig.samplers[c.sampler];
    rig.start = first ? s.times.front() : std::min(rig.start, s.times.front());
    rig.end = first ? s.times.back() : std::max(rig.end, s.times.back());
    first = false;
  }
  for (const int i : rig.order) {
    const int p = rig.nodes[size_t(i)].parent;
    rig.moving[size_t(i)] = animated[size_t(i)] || (p >= 0 && rig.moving[size_t(p)]);
  }
}

}  // namespace anamorph
