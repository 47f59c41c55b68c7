#include "app/interrupt.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>

#include "app/common.h"
#include "dist/world.h"
#include "io/temporary_files.h"

namespace anamorph::app {

namespace {

std::atomic<bool> g_interrupted{false};
std::atomic<bool> g_render_phase{false};
std::atomic<int> g_repeats{0};  // signals after the first within a render phase
std::atomic<pid_t> g_child{0};
// A worker rank of an MPI job stops without a word: mpirun says why the job ended.
volatile sig_atomic_t g_silent_interrupt = 0;
// The message, written by the handler as it is (no formatting in a signal handler).
char g_note[1024] = "\ninterrupted\n";
std::atomic<size_t> g_note_size{std::strlen("\ninterrupted\n")};

void say(const char* text, size_t size) {
  if (!g_silent_interrupt) {
    [[maybe_unused]] const ssize_t n = write(STDERR_FILENO, text, size);
  }
}

// Async-signal-safe from here on: atomics, kill(2), unlink(2), write(2) and _exit(2) only.
void on_interrupt(int) {
  if (g_render_phase.load()) {
    if (!g_interrupted.exchange(true)) return;  // the renderer stops; the image so far is written
    if (g_repeats.fetch_add(1) == 0) {
      static const char kAgain[] =
          "\ninterrupted again: writing the image so far first (a third signal abandons it)\n";
      say(kAgain, sizeof kAgain - 1);
      return;
    }
  }
  if (const pid_t child = g_child.load(); child > 0) kill(child, SIGTERM);
  remove_temporaries_now();
  say(g_note, g_note_size.load());
  _exit(kInterrupted);
}

}  // namespace

void install_interrupt_handlers() {
  g_silent_interrupt = dist::World::rank() > 0;
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGQUIT}) sigaction(sig, &sa, nullptr);
  // nohup's SIG_IGN is what it asks for: a render that outlives its terminal.
  struct sigaction old {};
  if (sigaction(SIGHUP, nullptr, &old) == 0 && old.sa_handler != SIG_IGN)
    sigaction(SIGHUP, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
}

const std::atomic<bool>& interrupt_flag() { return g_interrupted; }
RenderPhase::RenderPhase() { g_render_phase = true; }
RenderPhase::~RenderPhase() { g_render_phase = false; }

void set_interrupt_note(const std::string& note) {
  const std::string text = note.empty() ? "\ninterrupted\n" : "\ninterrupted: " + note + "\n";
  const size_t n = std::min(text.size(), sizeof g_note);
  g_note_size = 0;  // (a signal meanwhile prints nothing rather than half a message)
  std::memcpy(g_note, text.data(), n);
  g_note_size = n;
}

void set_child_to_stop(pid_t pid) { g_child = pid; }

void stop_signal_set(sigset_t* set) {
  sigemptyset(set);
  for (int sig : {SIGINT, SIGTERM, SIGQUIT}) sigaddset(set, sig);
  struct sigaction old {};
  if (sigaction(SIGHUP, nullptr, &old) == 0 && old.sa_handler != SIG_IGN) sigaddset(set, SIGHUP);
}

}  // namespace anamorph::app
