// `anamorph render --frames A:B --video FILE`: the frames assembled into a video by ffmpeg.
#pragma once

#include <string>

namespace anamorph::app {

// Whether ffmpeg is on the PATH; if not, says so (the caller exits 2 before rendering a frame).
bool video_tool_found();

// Runs ffmpeg over the frames `pattern` (printf, frames from `first`, `count` of them) into
// `video`. ffmpeg writes a temporary file beside it (the same extension, so it picks the same
// container), renamed into place once ffmpeg succeeds: a failed or interrupted run leaves the
// old video, or none, and no temporary (a signal stops ffmpeg too: app/interrupt.h). A device
// or FIFO is written directly. Returns an exit code; errors are printed.
int assemble_video(const std::string& pattern, int first, int count, int fps,
                   const std::string& video, bool quiet);

}  // namespace anamorph::app
