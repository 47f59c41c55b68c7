// Strict reading of TOML tables: typed getters with range checks, errors that name the file,
// line, column and dotted key, and unknown keys rejected with a "did you mean" suggestion.
#pragma once

#include <optional>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "camera/param_toml.h"
#include "camera/params.h"
#include "math/transform.h"
#include "math/vec.h"

namespace anamorph {

struct SourceLoc {
  std::string file;
  int line = 0, column = 0;
};

// A bad scene: reported to the user as "file:line:col: key: message", exit code 2.
class SceneError : public std::runtime_error {
 public:
  SceneError(const SourceLoc& loc, std::string key, const std::string& msg);
  SourceLoc loc;
  std::string key;
};

SourceLoc loc_of(const toml::node& n);
SourceLoc loc_of(const toml::key& k);

class TableReader {
 public:
  // `path` is the dotted key of the table (e.g. "camera", "object[2]").
  TableReader(const toml::table& t, std::string path);

  const toml::table& table() const { return t_; }
  const std::string& path() const { return path_; }
  std::string full_key(std::string_view key) const;
  bool has(std::string_view key) const { return t_.contains(key); }
  // Marks a key as accepted without reading it here.
  void allow(std::string_view key) {
    used_.insert(std::string(key));
    known_.insert(std::string(key));
  }
  const toml::node* node(std::string_view key);  // marks used; nullptr when absent

  double number(std::string_view key, double def, double lo = -kInf, double hi = kInf);
  double required_number(std::string_view key, double lo = -kInf, double hi = kInf);
  int64_t integer(std::string_view key, int64_t def, int64_t lo, int64_t hi);
  bool boolean(std::string_view key, bool def);
  std::string string(std::string_view key, std::string def,
                     std::span<const std::string_view> choices = {});
  Vec3 vec3(std::string_view key, Vec3 def);
  std::optional<Vec3> optional_vec3(std::string_view key);
  Color color(std::string_view key, Color def);  // [r,g,b] or a single number (grey)
  Transform transform(std::string_view key);     // identity when absent

  // Parameters declared by a ParamSpec table (camera functions and presets).
  ParamValues params(std::span<const ParamSpec> specs);

  // Throws on any key that was not read or allowed, suggesting the closest known key.
  void finish();

  [[noreturn]] void fail(std::string_view key, const std::string& msg) const;
  [[noreturn]] void fail_at(const toml::node& n, std::string_view key,
                            const std::string& msg) const;

 private:
  void mark(std::string_view key);
  const toml::table& t_;
  std::string path_;
  std::set<std::string, std::less<>> used_, known_;
};

// Reads a value of the given spec type from a TOML node (shared by params() and nested tables).
ParamValue read_param_value(TableReader& r, const ParamSpec& spec, const toml::node& n);

// Values as TOML text, for metadata and `anamorph info`.
std::string to_toml_text(const toml::table& t);

}  // namespace anamorph
