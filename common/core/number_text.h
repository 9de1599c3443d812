// The text of a double that reads back as the same double: the shortest such digits (what
// std::to_chars gives), in fixed or scientific notation, whichever is shorter. Used wherever a
// number is printed to be read again: cfg values and the effective configuration, the stream
// trace, the encoder's summary.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace tdvo {

#if defined(__EMSCRIPTEN__)
// Emscripten's libc++ has no floating-point std::to_chars: the same text (the shortest digits
// that read back as v, in fixed or scientific notation, whichever is shorter, fixed on a tie)
// from printf's digits, so that error messages are those of the native decoder.
inline std::string formatDouble(double v) {
  if (std::isnan(v)) return std::signbit(v) ? "-nan" : "nan";
  if (std::isinf(v)) return v < 0 ? "-inf" : "inf";
  const std::string sign = std::signbit(v) ? "-" : "";
  if (v == 0) return sign + "0";
  char buffer[400];
  for (int precision = 0;; ++precision) {
    std::snprintf(buffer, sizeof buffer, "%.*e", precision, std::fabs(v));
    if (std::strtod(buffer, nullptr) == std::fabs(v) || precision == 16) break;
  }
  // buffer: d[.ddd]e[+-]xx
  std::string digits;
  const char* p = buffer;
  for (; *p != 'e'; ++p)
    if (*p != '.') digits += *p;
  const int exponent = std::atoi(p + 1);
  const int count = static_cast<int>(digits.size());
  std::string scientific = digits.substr(0, 1);
  if (count > 1) scientific += "." + digits.substr(1);
  const int magnitude = std::abs(exponent);
  scientific += std::string(exponent < 0 ? "e-" : "e+") + (magnitude < 10 ? "0" : "") +
                std::to_string(magnitude);
  std::string fixed;
  if (exponent < 0)
    fixed = "0." + std::string(static_cast<size_t>(-exponent - 1), '0') + digits;
  else if (count - 1 <= exponent)  // an integer: fixed notation prints its exact value
    fixed = (std::snprintf(buffer, sizeof buffer, "%.0f", std::fabs(v)), buffer);
  else
    fixed = digits.substr(0, static_cast<size_t>(exponent + 1)) + "." +
            digits.substr(static_cast<size_t>(exponent + 1));
  return sign + (scientific.size() < fixed.size() ? scientific : fixed);
}
#else
inline std::string formatDouble(double v) {
  char buffer[32];
  auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, r.ptr);
}
#endif

}  // namespace tdvo
