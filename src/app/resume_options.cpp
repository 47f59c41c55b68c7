#include "app/resume_options.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>

namespace anamorph::app {

namespace {

// The long names of the options honoured beside --resume (and --resume itself).
constexpr std::array<std::string_view, 5> kHonoured = {"resume", "threads", "quiet",
                                                       "checkpoint-every", "skip-existing"};

bool honoured(const CLI::Option& o) {
  return std::any_of(o.get_lnames().begin(), o.get_lnames().end(), [](const std::string& n) {
    return std::find(kHonoured.begin(), kHonoured.end(), n) != kHonoured.end();
  });
}

// The option as a user would recognize it: its shortest name ("-o"), or the positional's.
std::string typed_name(const CLI::Option& o) {
  if (!o.get_snames().empty()) return "-" + o.get_snames().front();
  if (!o.get_lnames().empty()) return "--" + o.get_lnames().front();
  return o.get_name(true);
}

// Whether argument `a` gives option `name` ("--threads", "--threads=4").
bool names(const std::string& a, const std::string& name) {
  return a == name || a.starts_with(name + "=");
}

}  // namespace

ResumeOptions resume_options(const CLI::App& cmd) {
  ResumeOptions r;
  for (const CLI::Option* o : cmd.get_options()) {
    if (o->count() == 0 || o->get_lnames() == std::vector<std::string>{"help"}) continue;
    if (!honoured(*o)) {
      r.refused.push_back(typed_name(*o));
      continue;
    }
    if (o->get_lnames().front() == "resume") continue;
    std::optional<std::string> value;
    if (o->get_items_expected_max() > 0) value = o->results().back();
    r.honoured.emplace_back("--" + o->get_lnames().front(), value);
  }
  return r;
}

std::string refused_message(const ResumeOptions& r) {
  std::string list;
  for (const std::string& n : r.refused) list += (list.empty() ? "" : ", ") + n;
  return "--resume continues the render exactly as the checkpoint's command started it, so " +
         list + " would be ignored: leave " + (r.refused.size() == 1 ? "it" : "them") +
         " out, or render anew without --resume (only " + kWithResume +
         " may be given with --resume)";
}

void apply_honoured(const ResumeOptions& r, std::vector<std::string>& args) {
  for (const auto& [name, value] : r.honoured) {
    // The checkpoint's own occurrence goes ("--threads 4", "--threads=4"; -q for --quiet).
    for (size_t k = 0; k < args.size();) {
      if (names(args[k], name) || (name == "--quiet" && args[k] == "-q")) {
        const bool separate = value && args[k] == name && k + 1 < args.size();
        args.erase(args.begin() + long(k), args.begin() + long(k + (separate ? 2 : 1)));
      } else {
        ++k;
      }
    }
    args.push_back(name);
    if (value) args.push_back(*value);
  }
}

}  // namespace anamorph::app
