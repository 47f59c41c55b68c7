// Signals that end a run: SIGINT, SIGTERM, SIGHUP (unless ignored, as under nohup) and SIGQUIT
// all mean "stop": exit code 3 (kInterrupted) with a message, and no temporary file left
// (io/temporary_files.h). While a RenderPhase is alive the first one only sets interrupt_flag():
// the renderer stops at its next packet and the run writes the image so far (NAME.partial.EXT);
// a second one while that is being written is answered with a message and does not stop it (a
// third does). SIGPIPE is ignored: a write to a closed pipe fails with EPIPE and becomes an
// error message (exit 1) instead of a silent death.
#pragma once

#include <signal.h>
#include <sys/types.h>

#include <atomic>
#include <string>

namespace anamorph::app {

void install_interrupt_handlers();
const std::atomic<bool>& interrupt_flag();

struct RenderPhase {
  RenderPhase();
  ~RenderPhase();
  RenderPhase(const RenderPhase&) = delete;
  RenderPhase& operator=(const RenderPhase&) = delete;
};

// What an interruption outside a render phase says after "interrupted: ", e.g. "rays.csv not
// written" ("" : just "interrupted").
void set_interrupt_note(const std::string& note);

// A child process (ffmpeg) that an interruption stops too (SIGTERM); 0: none.
void set_child_to_stop(pid_t pid);

// The signals serve waits for with sigwait (blocked in every thread): SIGINT, SIGTERM, SIGQUIT and
// SIGHUP unless it is ignored.
void stop_signal_set(sigset_t* set);

}  // namespace anamorph::app
