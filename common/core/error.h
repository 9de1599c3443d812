// Error reporting for 3DVO: one exception type, thrown on bad input of any kind (files, cfg,
// streams) and caught in each app's main, which prints it as one line and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace tdvo {

// `message` with its control characters (a NUL, a line end, ESC, ...; bytes 0 .. 31 and 127)
// shown as \xNN: a message quotes input (a token of a file, a cfg value), and must stay one
// whole line on a terminal (a NUL cut it short where it was printed).
inline std::string oneLine(const std::string& message) {
  static const char hex[] = "0123456789abcdef";
  std::string shown;
  shown.reserve(message.size());
  for (const char c : message) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      shown += "\\x";
      shown += hex[u >> 4];
      shown += hex[u & 15];
    } else {
      shown += c;
    }
  }
  return shown;
}

// A user-facing error. The message names the place (file and line, or stream unit and byte
// offset) and what is wrong, e.g. "horse.obj:12: face index 9000 out of range (8431 vertices)";
// it is kept to one line (oneLine).
struct Error : std::runtime_error {
  explicit Error(const std::string& message) : std::runtime_error(oneLine(message)) {}
  explicit Error(const char* message) : Error(std::string(message)) {}
};

// CHECK-style helper: throws Error with the message when the condition does not hold. Used for
// every check on input data; never assert() on data that comes from outside.
inline void check(bool condition, const std::string& message) {
  if (!condition) throw Error(message);
}

}  // namespace tdvo
