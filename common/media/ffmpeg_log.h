// FFmpeg's own log lines. By default FFmpeg prints its messages to stderr as it goes, so a damaged
// input showed FFmpeg's lines before (and instead of being part of) the app's one error line.
// routeFfmpegLog() replaces FFmpeg's printer, once per process: messages below the error level
// (warnings, information) are dropped, and error messages are kept, per thread, for the code that
// called FFmpeg to take and put into its own error (or to treat as damage). With the environment
// variable TDVO_FFMPEG_LOG set, every message is printed to stderr as well, for debugging.
#pragma once

#include <string>

namespace tdvo {

void routeFfmpegLog();

// The first FFmpeg error message this thread logged since the last call ("" when none), without
// its trailing newline.
std::string takeFfmpegError();

}  // namespace tdvo
