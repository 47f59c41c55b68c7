// Running the anamorph binary from tests, as a user would from a shell.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "test_util.h"

namespace anamorph::test {

struct CliResult {
  int code;         // exit code; -1 when killed (by a signal, or by `timeout`)
  std::string out;  // stdout and stderr together
};

// Arguments quoted for a shell command line.
inline std::string join(const std::vector<std::string>& args) {
  std::string s;
  for (const auto& a : args) s += "'" + a + "' ";
  return s;
}

// A shell command line (sh -c), its exit code and output.
inline CliResult run_shell(const std::string& command, bool killed_is_137 = false) {
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  const int status = pclose(p);
  const bool exited = WIFEXITED(status) && !(killed_is_137 && WEXITSTATUS(status) == 137);
  return {exited ? WEXITSTATUS(status) : -1, out};
}

// Starts `anamorph ARGS` in the background (to signal it while it runs): stderr goes to `log`,
// stdout too unless `keep_stdout`. Returns its pid.
inline pid_t spawn(const std::vector<std::string>& args, const std::filesystem::path& log,
                   bool keep_stdout = false) {
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string bin = binary().string();
    std::vector<char*> argv{const_cast<char*>(bin.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    if (!freopen(log.c_str(), "w", stderr)) _exit(126);
    if (!keep_stdout && !freopen("/dev/null", "w", stdout)) _exit(126);
    execv(bin.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

// True when a sanitized run died in LeakSanitizer's own at-exit machinery (its thread-stopping
// tracer crashed: a known intermittent failure of the tool, google/sanitizers#1353), not in
// the program: no leak was reported, the check itself did not run.
inline bool leak_checker_crashed(const CliResult& r) {
  return r.code == 134 &&
         r.out.find("LeakSanitizer has encountered a fatal error") != std::string::npos &&
         r.out.find("Tracer caught signal") != std::string::npos;
}

// `anamorph ARGS`; with limit_seconds > 0, under `timeout -s KILL`, so a hang fails the test
// instead of stalling the suite. A run whose leak checker crashed is run once more (and said).
inline CliResult run_cli(const std::string& args, int limit_seconds = 0) {
  const std::string prefix =
      limit_seconds > 0 ? "timeout -s KILL " + std::to_string(limit_seconds) + " " : "";
  const std::string command = prefix + binary().string() + " " + args;
  CliResult r = run_shell(command, limit_seconds > 0);
  if (!leak_checker_crashed(r)) return r;
  std::printf("note: LeakSanitizer's tracer crashed at exit; running once more: %s\n%s",
              args.c_str(), r.out.c_str());
  return run_shell(command, limit_seconds > 0);
}

}  // namespace anamorph::test
