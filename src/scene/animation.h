// Keyframed scene keys: `[[animate]] key = "camera.coin.0.strength", keys = [[0, 0.0], [59, 1.0]],
// interpolation = "linear" | "smooth" | "step"`. Any numeric key can be animated, including arrays
// of numbers (points, colours, a row of control points): values interpolate component-wise;
// "step" holds each key's value until the next key (for integer keys such as image.width). Each
// frame's values are applied to the scene text before it is interpreted, exactly as --set would,
// so a frame of an animation equals a still render with those values set.
#pragma once

#include <string>
#include <vector>

#include <toml++/toml.h>

#include "scene/toml_reader.h"

namespace anamorph {

struct AnimatedKey {
  std::string key;
  enum class Interp { Linear, Smooth, Step } interp = Interp::Linear;  // smooth: Catmull-Rom, C1
  std::vector<double> frames;
  std::vector<std::vector<double>> values;  // flattened numbers per key
  toml::array shape;                        // the first key's value, whose shape results take
  std::vector<toml::array> raw;             // each key's value as written (for "step")
  SourceLoc loc;
};

// Reads and removes the top-level [[animate]] entries.
std::vector<AnimatedKey> take_animation(toml::table& root);

// The value at (fractional) frame f, clamped to the first and last keys.
std::vector<double> evaluate(const AnimatedKey& a, double f);
// The same as a TOML node of the key's shape, as { v = ... }: floats, except that "step" returns
// the key's value exactly as written.
toml::table value_node(const AnimatedKey& a, double f);

// An error about a value that an entry of `animation` gave its key at `frame` (such a value has
// no place in a file, and would be reported as "--set"), unless a --set in `overrides` replaced
// it: the same error at the entry's `key`, naming the frame. Other errors come back unchanged.
SceneError at_animate_entry(const SceneError& e, const std::vector<AnimatedKey>& animation,
                            const std::vector<std::string>& overrides, double frame);

}  // namespace anamorph
