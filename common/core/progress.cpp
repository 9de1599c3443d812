#include "common/core/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace tdvo {

namespace {

std::string duration(double seconds) {
  const long long s = std::llround(std::max(seconds, 0.0));
  if (s < 60) return std::to_string(s) + " s";
  if (s < 3600) return std::to_string(s / 60) + " min " + std::to_string(s % 60) + " s";
  return std::to_string(s / 3600) + " h " + std::to_string(s % 3600 / 60) + " min";
}

}  // namespace

Progress::Progress(std::string label, size_t total)
    : label_(std::move(label)),
      total_(total),
      enabled_(::isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() {
  if (enabled_) std::fprintf(stderr, "\r\033[K");
}

std::string Progress::line(const std::string& label, size_t done, size_t total,
                           double elapsedSeconds) {
  std::string out = label + " " + std::to_string(done) + "/" + std::to_string(total);
  if (done > 0 && done < total)
    out +=
        ", about " +
        duration(elapsedSeconds / static_cast<double>(done) * static_cast<double>(total - done)) +
        " left";
  return out;
}

void Progress::tick(size_t done) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (done < total_ && now - last_ < std::chrono::milliseconds(100)) return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  // \033[K clears what a longer earlier line left at its end.
  std::fprintf(stderr, "\r%s\033[K", line(label_, done, total_, elapsed).c_str());
  std::fflush(stderr);
}

}  // namespace tdvo
