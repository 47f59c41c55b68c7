// `anamorph schema`: the scene format as a JSON Schema (for editors: Taplo / Even Better TOML,
// VS Code, the editor's panels), and with --docs the generated parts of the documentation.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <vector>

#include "app/common.h"
#include "app/output_guard.h"
#include "io/image_io.h"
#include "io/read_file.h"
#include "scene/scene_schema.h"

namespace anamorph::app {

namespace {

namespace fs = std::filesystem;

struct SchemaArgs {
  std::string output;  // "" = stdout
  std::string docs;    // a docs/ folder to update
};

std::string read_text(const fs::path& p) {
  std::vector<unsigned char> bytes;
  if (const auto failure = read_whole_file(p, &bytes, kTextInput))
    throw std::runtime_error(describe(*failure, p));
  return std::string(bytes.begin(), bytes.end());
}

void write_text(const fs::path& p, const std::string& text) {
  write_file_atomic(p, text.data(), text.size());
}

int run(const SchemaArgs& a) {
  if (!a.docs.empty()) {
    const fs::path dir = a.docs;
    const fs::path format = dir / "scene-format.md";
    std::string doc = read_text(format);
    for (std::string_view block : scene_doc_blocks())
      doc = with_generated_block(doc, block, scene_doc_block(block));
    write_text(format, doc);
    const fs::path functions = dir / "functions.md";
    write_text(functions, with_generated_block(read_text(functions), "functions",
                                               function_reference_markdown()));
    fmt::print("updated {} and {}\n", format.string(), functions.string());
    return kOk;
  }
  if (!a.output.empty()) check_outputs({}, {{a.output, "-o " + a.output}});
  const std::string schema = scene_json_schema();
  if (a.output.empty())
    fmt::print("{}", schema);
  else
    write_text(a.output, schema);
  return kOk;
}

}  // namespace

void add_schema(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<SchemaArgs>();
  CLI::App* cmd = app.add_subcommand(
      "schema",
      "Print the scene format as a JSON Schema (draft 2020-12), generated from the declared keys");
  cmd->add_option("-o,--output", a->output, "Write the schema to this file instead of stdout");
  cmd->add_option("--docs", a->docs,
                  "Instead, regenerate the key tables of DIR/scene-format.md and DIR/functions.md")
      ->check(CLI::ExistingDirectory);
  cmd->callback([a, &runner] { runner = [a] { return run(*a); }; });
}

}  // namespace anamorph::app
