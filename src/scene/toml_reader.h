// Strict reading of TOML tables by their declared keys (scene_schema.h, params/read_params.h):
// errors that name the file, line, column and dotted key, and unknown keys rejected with a "did
// you mean" suggestion.
#pragma once

#include <initializer_list>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "math/transform.h"
#include "math/vec.h"
#include "params/param_toml.h"
#include "params/params.h"
#include "params/read_params.h"
#include "scene/scene_schema.h"

namespace anamorph {

struct SourceLoc {
  std::string file;
  int line = 0, column = 0;
};

// A bad scene: reported to the user as "file:line:col: key: message", exit code 2. what() has
// the user's text (file, key, quoted values) escaped (math/user_text.h); `key` and `message` are
// kept as they are (the editor sends them as JSON).
class SceneError : public std::runtime_error {
 public:
  SceneError(const SourceLoc& loc, std::string key, const std::string& msg);
  SourceLoc loc;
  std::string key;
  std::string message;  // what is wrong, without the place and the key
};

SourceLoc loc_of(const toml::node& n);
SourceLoc loc_of(const toml::key& k);

// One table of a scene being read: its dotted path for messages, and the walker (read_params)
// with the scene's hooks: errors carry file, line, column and dotted key; `file` values resolve
// against the file that names them and must exist; nested tables are origin functions or
// textures. Every key enters through params() (or, for structural keys a caller declares as
// `also`: sub-tables and arrays of tables, through node()).
class TableReader {
 public:
  // `path` is the dotted key of the table (e.g. "camera", "object[2]").
  TableReader(const toml::table& t, std::string path);

  const toml::table& table() const { return t_; }
  const std::string& path() const { return path_; }
  std::string full_key(std::string_view key) const;
  bool has(std::string_view key) const { return t_.contains(key); }
  const toml::node* node(std::string_view key) const { return t_.get(key); }

  // The declared keys of `groups` (defaults filled in); any other key is an error unless named
  // in `also`.
  ParamValues params(std::initializer_list<std::span<const ParamSpec>> groups,
                     std::span<const std::string_view> also = {}) const;
  // The value of a selector key (a String spec with choices, e.g. `type`), its default when
  // absent; "is required (one of: ...)" when it has none.
  std::string selector(const ParamSpec& spec) const;
  // A table with a selector (an object's `type`): its common keys and its form's own.
  ParamValues params(const TableSchema& schema, std::span<const std::string_view> also = {}) const;

  [[noreturn]] void fail(std::string_view key, const std::string& msg) const;
  [[noreturn]] void fail_at(const toml::node& n, std::string_view key,
                            const std::string& msg) const;

 private:
  ParamWalk walk(std::span<const std::string_view> also) const;
  const toml::table& t_;
  std::string path_;
};

// Values as TOML text, for metadata and `anamorph info`.
std::string to_toml_text(const toml::table& t);

}  // namespace anamorph
