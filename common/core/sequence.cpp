#include "common/core/sequence.h"

#include <climits>
#include <cstdio>
#include <filesystem>

#include "common/core/error.h"

namespace tdvo {

namespace {

// Finds the single conversion; returns its [start, end) in the pattern and its width/zero flag.
struct Conversion {
  size_t start = std::string::npos, end = 0;
  int width = 0;
  bool zeroPad = false;
};

Conversion findConversion(const std::string& pattern, const std::string& what) {
  Conversion conversion;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') continue;
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      ++i;
      continue;
    }
    size_t j = i + 1;
    Conversion c;
    c.start = i;
    if (j < pattern.size() && pattern[j] == '0') {
      c.zeroPad = true;
      ++j;
    }
    while (j < pattern.size() && pattern[j] >= '0' && pattern[j] <= '9' && c.width < 100)
      c.width = c.width * 10 + (pattern[j++] - '0');
    if (j >= pattern.size() || pattern[j] != 'd' || c.width > 32)
      throw Error(what + ": '" + pattern + "': only %d, %Nd and %0Nd conversions are allowed");
    if (conversion.start != std::string::npos)
      throw Error(what + ": '" + pattern + "' has more than one frame-number conversion");
    c.end = j + 1;
    conversion = c;
    i = j;
  }
  if (conversion.start == std::string::npos)
    throw Error(what + ": '" + pattern + "' needs one frame-number conversion such as %04d");
  return conversion;
}

std::string unescape(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    out += s[i];
    if (s[i] == '%' && i + 1 < s.size() && s[i + 1] == '%') ++i;
  }
  return out;
}

}  // namespace

void checkFramePattern(const std::string& pattern, const std::string& what) {
  findConversion(pattern, what);
}

void checkOutputFramePattern(const std::string& pattern, const std::string& what) {
  checkFramePattern(pattern, what);
  if (!pattern.empty() && pattern[0] == '/')
    throw Error(what + ": '" + pattern +
                "' is an absolute path; it names files inside the output folder (give a relative "
                "path)");
}

std::string framePath(const std::string& pattern, int frame) {
  const Conversion c = findConversion(pattern, "frame pattern");
  char number[48];
  std::snprintf(number, sizeof number, c.zeroPad ? "%0*d" : "%*d", c.width, frame);
  return unescape(pattern.substr(0, c.start)) + number + unescape(pattern.substr(c.end));
}

std::string escapePercent(const std::string& literal) {
  std::string out;
  for (const char c : literal) {
    out += c;
    if (c == '%') out += '%';
  }
  return out;
}

std::string unescapePercent(const std::string& text) {
  return unescape(text);
}

std::optional<std::string> firstFileAfter(const std::string& pattern, int number) {
  const size_t slash = pattern.rfind('/');
  const std::string folder = slash == std::string::npos ? "." : pattern.substr(0, slash);
  if (slash != std::string::npos && findConversion(pattern, "frame pattern").start < slash)
    return std::nullopt;  // the number is in a folder name
  const std::string prefix =
      slash == std::string::npos ? "" : unescape(pattern.substr(0, slash + 1));
  std::error_code ec;
  std::optional<int> later;
  std::string path;
  for (std::filesystem::directory_iterator it(slash == 0 ? "/" : unescape(folder), ec), end;
       !ec && it != end; it.increment(ec)) {
    const std::string candidate = prefix + it->path().filename().string();
    const std::optional<int> frame = frameOfPath(pattern, candidate);
    if (frame && *frame > number && (!later || *frame < *later)) {
      later = frame;
      path = candidate;
    }
  }
  if (!later) return std::nullopt;
  return path;
}

std::optional<int> frameOfPath(const std::string& pattern, const std::string& path) {
  const Conversion c = findConversion(pattern, "frame pattern");
  const std::string prefix = unescape(pattern.substr(0, c.start));
  const std::string suffix = unescape(pattern.substr(c.end));
  if (path.size() < prefix.size() + suffix.size() + 1 || path.compare(0, prefix.size(), prefix) ||
      path.compare(path.size() - suffix.size(), suffix.size(), suffix))
    return std::nullopt;
  const std::string number =
      path.substr(prefix.size(), path.size() - prefix.size() - suffix.size());
  // The number as framePath writes it: blanks (%Nd), a sign, digits; an int has at most 10.
  size_t i = number.find_first_not_of(' ');
  if (i == std::string::npos) return std::nullopt;
  const bool negative = number[i] == '-';
  i += negative;
  if (i == number.size() || number.size() - i > 10 ||
      number.find_first_not_of("0123456789", i) != std::string::npos)
    return std::nullopt;
  const long long magnitude = std::stoll(number.substr(i));
  const long long value = negative ? -magnitude : magnitude;
  if (value < INT_MIN || value > INT_MAX) return std::nullopt;
  const int frame = static_cast<int>(value);
  if (framePath(pattern, frame) != path) return std::nullopt;
  return frame;
}

}  // namespace tdvo
