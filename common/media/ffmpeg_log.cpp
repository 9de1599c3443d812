#include "common/media/ffmpeg_log.h"

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <mutex>

extern "C" {
#include <libavutil/log.h>
}

namespace tdvo {

namespace {

thread_local std::string firstError;
bool echo = false;

void logCallback(void* object, int level, const char* format, va_list args) {
  if (level > AV_LOG_ERROR && !echo) return;
  char line[1024];
  int printPrefix = 0;  // no "[h264 @ 0x...]": the address differs from run to run
  av_log_format_line2(object, level, format, args, line, sizeof line, &printPrefix);
  if (echo) std::fputs(line, stderr);
  if (level > AV_LOG_ERROR || !firstError.empty()) return;
  std::string text = line;
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' '))
    text.pop_back();
  firstError = text.empty() ? std::string("(empty FFmpeg error message)") : text;
}

}  // namespace

void routeFfmpegLog() {
  static std::once_flag once;
  std::call_once(once, [] {
    echo = std::getenv("TDVO_FFMPEG_LOG") != nullptr;
    av_log_set_callback(logCallback);
  });
}

std::string takeFfmpegError() {
  std::string out;
  out.swap(firstError);
  return out;
}

}  // namespace tdvo
