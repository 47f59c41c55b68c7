#include "server/document_save.h"

#include <algorithm>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "server/document.h"

namespace anamorph::server {

namespace {

bool same(const toml::node& a, const toml::node& b) {
  toml::table x, y;
  x.insert("v", a);
  y.insert("v", b);
  return x == y;
}

bool block_table(const toml::node& n) {
  const toml::table* t = n.as_table();
  return t && !t->is_inline();
}

// An array written as [[key]] blocks (its entries are tables with headers of their own).
bool block_array(const toml::node& n) {
  const toml::array* a = n.as_array();
  return a && !a->empty() && a->is_array_of_tables() && block_table(*a->get(0));
}

std::string key_text(std::string_view k) {
  const bool bare = !k.empty() && std::all_of(k.begin(), k.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  if (bare) return std::string(k);
  std::ostringstream os;
  os << toml::value<std::string>(std::string(k));
  return os.str();
}

// TOML as toml++ writes it, with strings in double quotes (as scene files write them; toml++
// prefers 'literal' strings) and floats in their shortest form.
std::string format(const toml::table& t) {
  constexpr auto flags = toml::toml_formatter::default_flags & ~toml::format_flags::indentation &
                         ~toml::format_flags::allow_literal_strings;
  std::ostringstream os;
  os << toml::toml_formatter(t, flags);
  return tidy_floats(os.str());
}

// A value as inline TOML text (tables inline).
std::string value_text(const toml::node& v) {
  toml::table t;
  t.insert("v", v);
  if (toml::table* inner = t.get("v")->as_table()) inner->is_inline(true);
  if (toml::array* a = t.get("v")->as_array())
    for (auto& e : *a)
      if (toml::table* et = e.as_table()) et->is_inline(true);
  std::string s = format(t);
  s = s.substr(s.find('=') + 2);
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

// Edits of the original text by byte ranges, applied from the end so offsets stay valid.
class Splicer {
 public:
  explicit Splicer(const std::string& text) : text_(text) {
    starts_.push_back(0);
    for (size_t i = 0; i < text.size(); ++i)
      if (text[i] == '\n') starts_.push_back(i + 1);
  }
  int lines() const { return int(starts_.size()); }
  // Line (1-based) start offset; one past the end for lines()+1.
  size_t line_start(int line) const {
    return line >= 1 && line <= lines() ? starts_[size_t(line - 1)] : text_.size();
  }
  std::string_view line_text(int line) const {
    const size_t b = line_start(line), e = line_start(line + 1);
    return std::string_view(text_).substr(b, e - b);
  }
  // toml++ counts columns in code points.
  size_t offset(const toml::source_position& p) const {
    size_t o = line_start(int(p.line));
    for (uint32_t col = 1; col < p.column && o < text_.size(); ++col) {
      ++o;
      while (o < text_.size() && (static_cast<unsigned char>(text_[o]) & 0xC0) == 0x80) ++o;
    }
    return o;
  }
  void replace(size_t b, size_t e, std::string s) { edits_.push_back({b, e, std::move(s)}); }
  void insert_after_line(int line, std::string s) {
    const size_t at = line_start(line + 1);
    const bool needs_newline = at == text_.size() && !text_.empty() && text_.back() != '\n';
    edits_.push_back({at, at, (needs_newline ? "\n" : "") + s});
  }
  void append(std::string block) {
    if (!block.empty() && block.back() != '\n') block += '\n';
    appended_ += "\n" + block;
  }
  std::optional<std::string> apply() const {
    std::vector<Edit> e = edits_;
    std::stable_sort(e.begin(), e.end(), [](const Edit& a, const Edit& b) { return a.b > b.b; });
    for (size_t i = 1; i < e.size(); ++i)
      if (e[i].e > e[i - 1].b && e[i].b != e[i].e) return std::nullopt;  // overlapping ranges
    std::string out = text_;
    for (const Edit& x : e) out.replace(x.b, x.e - x.b, x.s);
    if (!appended_.empty()) {
      if (!out.empty() && out.back() != '\n') out += '\n';
      out += appended_;
    }
    return out;
  }

 private:
  struct Edit {
    size_t b, e;
    std::string s;
  };
  const std::string& text_;
  std::vector<size_t> starts_;
  std::vector<Edit> edits_;
  std::string appended_;
};

// Walks the original tree and the document together and records each difference as a splice.
class Differ {
 public:
  Differ(Splicer& sp, const toml::table& original) : sp_(sp) {
    collect_headers(original);
    std::sort(headers_.begin(), headers_.end());
  }

  bool table(const toml::table& o, const toml::table& c, const std::vector<std::string>& path,
             bool in_array, bool root) {
    for (const auto& [k, cv] : c) {
      const toml::node* ov = o.get(k.str());
      std::vector<std::string> p = path;
      p.push_back(std::string(k.str()));
      if (!ov) {
        if (!add(o, p, cv, in_array, root)) return false;
      } else if (block_table(*ov) && cv.is_table()) {
        if (!table(*ov->as_table(), *cv.as_table(), p, in_array, false)) return false;
      } else if (block_array(*ov) && cv.is_array() && cv.as_array()->is_array_of_tables()) {
        if (!array(*ov->as_array(), *cv.as_array(), p, in_array)) return false;
      } else if (!same(*ov, cv)) {
        if (block_table(*ov) || block_array(*ov)) return false;
        sp_.replace(sp_.offset(ov->source().begin), sp_.offset(ov->source().end), value_text(cv));
      }
    }
    for (const auto& [k, ov] : o)
      if (!c.contains(k.str()) && !remove(k, ov)) return false;
    return true;
  }

 private:
  bool array(const toml::array& o, const toml::array& c, const std::vector<std::string>& path,
             bool in_array) {
    const size_t common = std::min(o.size(), c.size());
    for (size_t i = 0; i < common; ++i)
      if (!table(*o.get(i)->as_table(), *c.get(i)->as_table(), path, true, false)) return false;
    for (size_t i = common; i < o.size(); ++i)
      if (!remove_block(*o.get(i)->as_table())) return false;
    if (c.size() > o.size() && in_array) return false;
    for (size_t i = common; i < c.size(); ++i) {
      toml::array one;
      one.push_back(*c.get(i));
      sp_.append(block({path.begin(), path.end() - 1}, path.back(), one));
    }
    return true;
  }

  bool add(const toml::table& o, const std::vector<std::string>& path, const toml::node& v,
           bool in_array, bool root) {
    if (block_table(v) || (v.is_array() && v.as_array()->is_array_of_tables())) {
      if (in_array) return false;  // ([a.b] cannot name an entry of an array)
      sp_.append(block({path.begin(), path.end() - 1}, path.back(), v));
      return true;
    }
    int line = root ? 0 : int(o.source().begin.line);
    if (!root && !starts_with_bracket(sp_.line_text(line))) return false;  // (no header of its own)
    for (const auto& [k, child] : o)
      if (!block_table(child) && !block_array(child))
        line = std::max(line, int(child.source().end.line));
    sp_.insert_after_line(line, key_text(path.back()) + " = " + value_text(v) + "\n");
    return true;
  }

  bool remove(const toml::key& k, const toml::node& ov) {
    if (block_table(ov)) return remove_block(*ov.as_table());
    if (block_array(ov)) {
      for (const auto& e : *ov.as_array())
        if (!remove_block(*e.as_table())) return false;
      return true;
    }
    const int first = int(k.source().begin.line), last = int(ov.source().end.line);
    const std::string_view before = sp_.line_text(first).substr(0, k.source().begin.column - 1);
    const size_t end = sp_.offset(ov.source().end);
    const std::string_view after =
        std::string_view(sp_.line_text(last)).substr(end - sp_.line_start(last));
    if (!blank(before) || !(blank(after) || after.find_first_not_of(" \t") == after.find('#')))
      return false;
    sp_.replace(sp_.line_start(first), sp_.line_start(last + 1), "");
    return true;
  }

  // A table's block: its header line up to the next header. It must have no headers of its own
  // below (sub-tables written as blocks).
  bool remove_block(const toml::table& t) {
    for (const auto& [k, v] : t)
      if (block_table(v) || block_array(v)) return false;
    const int header = int(t.source().begin.line);
    if (!starts_with_bracket(sp_.line_text(header))) return false;
    const auto next = std::upper_bound(headers_.begin(), headers_.end(), header);
    const int end = next == headers_.end() ? sp_.lines() + 1 : *next;
    sp_.replace(sp_.line_start(header), sp_.line_start(end), "");
    return true;
  }

  // `value` as `key` of the table at `parents`, as the text of a block of its own.
  static std::string block(const std::vector<std::string>& parents, const std::string& key,
                           const toml::node& value) {
    toml::table root;
    toml::table* cur = &root;
    for (const std::string& p : parents)
      cur = cur->insert(p, toml::table{}).first->second.as_table();
    toml::node& v = cur->insert(key, value).first->second;
    // Written as a block of its own: [key] or [[key]], not an inline value under a header that
    // the file already has.
    if (toml::table* t = v.as_table()) t->is_inline(false);
    if (toml::array* a = v.as_array())
      for (auto& e : *a)
        if (toml::table* t = e.as_table()) t->is_inline(false);
    return normalized_text(root);
  }

  void collect_headers(const toml::table& t) {
    for (const auto& [k, v] : t) {
      if (block_table(v)) {
        headers_.push_back(int(v.source().begin.line));
        collect_headers(*v.as_table());
      } else if (block_array(v)) {
        for (const auto& e : *v.as_array()) {
          headers_.push_back(int(e.source().begin.line));
          collect_headers(*e.as_table());
        }
      }
    }
  }

  static bool blank(std::string_view s) {
    return s.find_first_not_of(" \t\r\n") == std::string_view::npos;
  }
  static bool starts_with_bracket(std::string_view line) {
    const size_t i = line.find_first_not_of(" \t");
    return i != std::string_view::npos && line[i] == '[';
  }

  Splicer& sp_;
  std::vector<int> headers_;
};

}  // namespace

std::string normalized_text(const toml::table& t) { return format(t); }

SavedText saved_text(const std::string& original_text, const toml::table& current) {
  try {
    const toml::table original = toml::parse(original_text);
    Splicer sp(original_text);
    Differ d(sp, original);
    if (d.table(original, current, {}, false, true)) {
      if (std::optional<std::string> text = sp.apply()) {
        // Kept only when it reads back as the document.
        if (toml::parse(*text) == current) return {*text, false};
      }
    }
  } catch (const toml::parse_error&) {
  }
  SavedText whole{normalized_text(current), true, false};
  try {
    whole.reads_back = toml::parse(whole.text) == current;
  } catch (const toml::parse_error&) {
  }
  return whole;
}

}  // namespace anamorph::server
