// Error reporting for 3DVO: one exception type, thrown on bad input of any kind (files, cfg,
// streams) and caught in each app's main, which prints it as one line and exits non-zero.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace tdvo {

// Length of the well-formed UTF-8 sequence that starts at text[i] (2 to 4 bytes; Unicode's
// table of well-formed byte sequences: no overlong forms, no surrogates, nothing above
// U+10FFFF), or 0 when the bytes there are not one.
inline std::size_t utf8SequenceLength(const std::string& text, std::size_t i) {
  const auto at = [&](std::size_t k) -> unsigned {
    return i + k < text.size() ? static_cast<unsigned char>(text[i + k]) : 0u;
  };
  const unsigned lead = at(0);
  std::size_t length = 0;
  unsigned low = 0x80, high = 0xbf;  // the range of the second byte
  if (lead >= 0xc2 && lead <= 0xdf) {
    length = 2;
  } else if (lead >= 0xe0 && lead <= 0xef) {
    length = 3;
    if (lead == 0xe0) low = 0xa0;
    if (lead == 0xed) high = 0x9f;
  } else if (lead >= 0xf0 && lead <= 0xf4) {
    length = 4;
    if (lead == 0xf0) low = 0x90;
    if (lead == 0xf4) high = 0x8f;
  } else {
    return 0;
  }
  if (at(1) < low || at(1) > high) return 0;
  for (std::size_t k = 2; k < length; ++k)
    if (at(k) < 0x80 || at(k) > 0xbf) return 0;
  return length;
}

// `message` with what a terminal must not be given shown as \xNN, byte by byte: control
// characters (a NUL, a line end, ESC, ...; bytes 0 .. 31 and 127, and the C1 controls U+0080 ..
// U+009F) and bytes that are not well-formed UTF-8 (a Latin-1 file name, a binary token). A
// message quotes input (a token of a file, a cfg value), and must stay one whole, readable line
// (a NUL cut it short where it was printed); well-formed UTF-8 text is kept as it is.
inline std::string oneLine(const std::string& message) {
  static const char hex[] = "0123456789abcdef";
  std::string shown;
  shown.reserve(message.size());
  const auto escape = [&](unsigned u) {
    shown += "\\x";
    shown += hex[u >> 4];
    shown += hex[u & 15];
  };
  for (std::size_t i = 0; i < message.size();) {
    const auto u = static_cast<unsigned char>(message[i]);
    if (u < 0x80) {
      if (u < 0x20 || u == 0x7f)
        escape(u);
      else
        shown += message[i];
      ++i;
      continue;
    }
    const std::size_t length = utf8SequenceLength(message, i);
    const bool c1 = length == 2 && u == 0xc2 && static_cast<unsigned char>(message[i + 1]) < 0xa0;
    if (length == 0 || c1) {
      const std::size_t n = length == 0 ? 1 : length;
      for (std::size_t k = 0; k < n; ++k)
        escape(static_cast<unsigned char>(message[i + k]));
      i += n;
    } else {
      shown.append(message, i, length);
      i += length;
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
