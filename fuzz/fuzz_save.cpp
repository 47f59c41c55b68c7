// Saving the editor's document (server/document_save.h): the input is a TOML text and, after a
// line "---", edits (one per line: KEY=VALUE, or KEY= to remove it). The saved text must read
// back as the edited document exactly, whether the edits were spliced into the file's text or
// the file was written whole; a splice that reads past the text or garbles it is a finding.
// (Edits that are not UTF-8 are skipped: the document refuses them, as Document::edited does.
// A document toml++ cannot write back at all, e.g. a key with control characters, is refused
// by the editor's save.)
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "scene/toml_edit.h"
#include "server/document_save.h"

using namespace anamorph;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > (1 << 16)) return 0;
  const std::string input(reinterpret_cast<const char*>(data), size);
  const size_t split = input.find("\n---\n");
  const std::string text = input.substr(0, split);
  toml::table t;
  try {
    t = toml::parse(text);
  } catch (const toml::parse_error&) {
    return 0;
  }
  if (split != std::string::npos) {
    size_t s = split + 5;
    for (int n = 0; s < input.size() && n < 16; ++n) {
      size_t e = input.find('\n', s);
      if (e == std::string::npos) e = input.size();
      const std::string line = input.substr(s, e - s);
      s = e + 1;
      const size_t eq = line.find('=');
      // (The editor's edits arrive as JSON, which is UTF-8; the document refuses anything else.)
      if (eq == std::string::npos || eq == 0 || !valid_utf8(line)) continue;
      try {
        if (eq + 1 == line.size())
          remove_path(t, line.substr(0, eq));
        else
          set_path(t, line.substr(0, eq), *parse_value_text(line.substr(eq + 1)).get("v"), {});
      } catch (const std::exception&) {  // (a key that is not there: a SceneError)
      }
    }
  }
  const server::SavedText saved = server::saved_text(text, t);
  if (!saved.reads_back) return 0;  // (the editor refuses to save it)
  try {
    if (toml::parse(saved.text) == t) return 0;
  } catch (const toml::parse_error& e) {
    std::fprintf(stderr, "does not parse: %s\n", std::string(e.description()).c_str());
  }
  std::fprintf(stderr, "saved (%s):\n%s\n", saved.normalized ? "normalized" : "spliced",
               saved.text.c_str());
  std::abort();
}
