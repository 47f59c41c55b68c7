#include "server/document.h"

#include <sstream>

#include <algorithm>
#include <cctype>
#include <charconv>

#include "io/read_file.h"
#include "params/toml_parse.h"
#include "scene/toml_edit.h"
#include "scene/toml_reader.h"
#include "server/document_save.h"

namespace anamorph::server {

namespace {

constexpr size_t kMaxUndo = 500;  // a long drag is many edits; memory stays a few MB

}  // namespace

// toml++ writes every float with 17 significant digits (0.8 as 0.80000000000000004); a saved
// scene should read as its author wrote it.
std::string tidy_floats(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (c == '"' || c == '\'') {  // a string: copied as it is (escapes included)
      size_t j = i + 1;
      while (j < text.size() && text[j] != c && text[j] != '\n')
        j += (c == '"' && text[j] == '\\') ? 2 : 1;
      j = std::min(j + 1, text.size());
      out.append(text, i, j - i);
      i = j;
      continue;
    }
    const bool starts_number =
        std::isdigit(static_cast<unsigned char>(c)) ||
        (c == '-' && i + 1 < text.size() && std::isdigit(static_cast<unsigned char>(text[i + 1])));
    // (after ':', the seconds of a time: 07:32:00.5 is no float)
    const bool after_word =
        i > 0 && (std::isalnum(static_cast<unsigned char>(text[i - 1])) || text[i - 1] == '_' ||
                  text[i - 1] == '.' || text[i - 1] == ':');
    if (!starts_number || after_word) {
      out.push_back(c);
      ++i;
      continue;
    }
    size_t j = i + 1;
    while (j < text.size() &&
           (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '.' || text[j] == '+' ||
            text[j] == '-' || text[j] == '_'))
      ++j;
    const std::string token = text.substr(i, j - i);
    double x = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), x);
    if (ec == std::errc() && end == token.data() + token.size() &&
        token.find_first_of(".eE") != std::string::npos) {
      char buf[64];
      const auto r = std::to_chars(buf, buf + sizeof buf, x);
      std::string shortest(buf, r.ptr);
      if (shortest.find_first_of(".eEn") == std::string::npos) shortest += ".0";
      out += shortest;
    } else {
      out += token;
    }
    i = j;
  }
  return out;
}

namespace {

bool is_view_key(std::string_view k) { return k == "camera" || k == "image" || k == "render"; }

bool animates_view(const toml::node& entry) {
  const toml::table* t = entry.as_table();
  const std::optional<std::string> key =
      t ? t->get("key") ? t->get("key")->value<std::string>() : std::nullopt : std::nullopt;
  if (!key) return false;
  const std::string_view first = std::string_view(*key).substr(0, key->find('.'));
  return is_view_key(first);
}

// The tree without what only the view depends on: [camera], [image], [render] and the
// [[animate]] entries of their keys.
toml::table without_view(const toml::table& t) {
  toml::table r;
  for (const auto& [k, v] : t) {
    if (is_view_key(k.str())) continue;
    if (k.str() == "animate" && v.is_array()) {
      toml::array rest;
      for (const auto& e : *v.as_array())
        if (!animates_view(e)) rest.push_back(e);
      r.insert(k, std::move(rest));
      continue;
    }
    r.insert(k, v);
  }
  return r;
}

}  // namespace

Document::Document(std::filesystem::path file) : file_(std::move(file)) {
  std::vector<unsigned char> bytes;
  if (const auto failure = read_whole_file(file_, &bytes, kSceneInput))
    throw SceneError({file_.string()}, "", describe(*failure, file_));
  original_text_.assign(bytes.begin(), bytes.end());
  try {
    table_ = parse_toml(original_text_, file_.string());
  } catch (const toml::parse_error& e) {
    SourceLoc l{file_.string(), int(e.source().begin.line), int(e.source().begin.column)};
    throw SceneError(l, "", std::string("TOML syntax error: ") + std::string(e.description()));
  }
}

SavedText Document::saved() const { return saved_text(original_text_, table_); }

std::string Document::text() const { return saved().text; }

namespace {

// Arrays of tables are written as [[key]] blocks, as scene files write coins, objects and
// keyframes, not as one long line of inline tables (an edit sets them as inline ones).
void block_arrays_of_tables(toml::node& n) {
  if (toml::table* t = n.as_table()) {
    for (auto&& [k, v] : *t) block_arrays_of_tables(v);
  } else if (toml::array* a = n.as_array(); a && !a->empty() && a->is_array_of_tables()) {
    for (auto& e : *a) {
      e.as_table()->is_inline(false);
      block_arrays_of_tables(e);
    }
  }
}

}  // namespace

toml::table Document::edited(std::span<const KeyEdit> edits) const {
  toml::table t = table_;
  for (const KeyEdit& e : edits) {
    if (e.key.empty()) throw SceneError({file_.string()}, "", "an edit needs a key");
    if (!valid_utf8(e.key) || (e.value && !valid_utf8(*e.value)))
      throw SceneError({file_.string()}, e.key, "not valid UTF-8 (a scene file is UTF-8 text)");
    if (e.value)
      set_path(t, e.key, *parse_value_text(*e.value, e.key).get("v"), {file_.string()});
    else
      remove_path(t, e.key);
  }
  block_arrays_of_tables(t);
  return t;
}

void Document::commit(toml::table next) {
  undo_.push_back(std::move(table_));
  if (undo_.size() > kMaxUndo) undo_.erase(undo_.begin());
  redo_.clear();
  table_ = std::move(next);
  ++version_;
}

bool Document::undo() {
  if (undo_.empty()) return false;
  redo_.push_back(std::move(table_));
  table_ = std::move(undo_.back());
  undo_.pop_back();
  ++version_;
  return true;
}

bool Document::redo() {
  if (redo_.empty()) return false;
  undo_.push_back(std::move(table_));
  table_ = std::move(redo_.back());
  redo_.pop_back();
  ++version_;
  return true;
}

bool differs_only_in_view(const toml::table& a, const toml::table& b) {
  return without_view(a) == without_view(b);
}

}  // namespace anamorph::server
