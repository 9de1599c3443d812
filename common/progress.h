// Progress on long runs: a counter line on stderr, redrawn in place, only when stderr is a
// terminal (logs and CI output stay clean).
#pragma once

#include <chrono>
#include <string>

namespace tdvo {

class Progress {
 public:
  Progress(std::string label, size_t total);
  ~Progress();
  void tick(size_t done);  // `done` of `total` items finished

 private:
  std::string label_;
  size_t total_;
  bool enabled_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace tdvo
