// Error reporting for 3DVO: one exception type, thrown on bad input of any kind (files, cfg,
// streams) and caught in each app's main, which prints it as one line and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace tdvo {

// A user-facing error. The message names the place (file and line, or stream unit and byte
// offset) and what is wrong, e.g. "horse.obj:12: face index 9000 out of range (8431 vertices)".
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// CHECK-style helper: throws Error with the message when the condition does not hold. Used for
// every check on input data; never assert() on data that comes from outside.
inline void check(bool condition, const std::string& message) {
  if (!condition) throw Error(message);
}

}  // namespace tdvo
