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
#include <string_view>
#include <system_error>
#include <type_traits>

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

// Reads the whole of `token` as a number of type T, as the C library's strtod reads text: an
// optional sign ('+' too), decimal or scientific digits ("inf" and "nan" included, which the
// caller judges). A floating-point value smaller than the type can hold rounds to it (to 0 or
// a subnormal), one larger becomes infinite: only text that is not a number is refused
// (false). Used by the mesh readers for every number of their text formats.
template <class T>
bool parseNumber(std::string_view token, T& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+')
    token.remove_prefix(1);
  const char* const end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ptr != end) return false;
  if (ec == std::errc()) return true;
  if constexpr (std::is_floating_point_v<T>) {
    if (ec == std::errc::result_out_of_range) {
      const std::string text(token);
      if constexpr (std::is_same_v<T, float>)
        value = std::strtof(text.c_str(), nullptr);
      else
        value = static_cast<T>(std::strtod(text.c_str(), nullptr));
      return true;
    }
  }
  return false;
}

}  // namespace tdvo
