// Progress on long runs: a counter line on stderr, redrawn in place, with an estimate of the
// time left, only when stderr is a terminal (logs and CI output stay clean).
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace tdvo {

class Progress {
 public:
  Progress(std::string label, size_t total);
  ~Progress();
  void tick(size_t done);  // `done` of `total` items finished

  // The line shown after `done` of `total` items in `elapsedSeconds`: "label done/total", and
  // while items remain, the time left at the average pace so far, e.g. "frame 3/10, about 14 s
  // left" (none before the first item is done).
  static std::string line(const std::string& label, size_t done, size_t total,
                          double elapsedSeconds);

 private:
  std::string label_;
  size_t total_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace tdvo
