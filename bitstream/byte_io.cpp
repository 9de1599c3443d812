#include "bitstream/byte_io.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "common/core/error.h"

namespace tdvo {

namespace {

#if defined(__EMSCRIPTEN__)
// Emscripten's libc++ has no floating-point std::to_chars: the same text (the shortest digits
// that read back as v, in fixed or scientific notation, whichever is shorter, fixed on a tie)
// from printf's digits, so that error messages are those of the native decoder.
std::string formatDouble(double v) {
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
std::string formatDouble(double v) {
  char buffer[32];
  auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, r.ptr);
}
#endif

void checkWrite(const char* name, uint64_t v, uint64_t min, uint64_t max) {
  if (v < min || v > max)
    throw std::logic_error(std::string("writing ") + name + " = " + std::to_string(v) +
                           " outside its range [" + std::to_string(min) + ", " +
                           std::to_string(max) + "]");
}

}  // namespace

// ---- ByteWriter ----

void ByteWriter::put(uint64_t v, int size) {
  for (int i = 0; i < size; ++i)
    data_.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

void ByteWriter::traceValue(const char* name, const std::string& value) {
  if (trace_) std::fprintf(trace_, "  %-32s = %s\n", name, value.c_str());
}

void ByteWriter::u8(const char* name, uint8_t& v, uint64_t min, uint64_t max) {
  checkWrite(name, v, min, max);
  traceValue(name, std::to_string(v));
  put(v, 1);
}

void ByteWriter::u16(const char* name, uint16_t& v, uint64_t min, uint64_t max) {
  checkWrite(name, v, min, max);
  traceValue(name, std::to_string(v));
  put(v, 2);
}

void ByteWriter::u32(const char* name, uint32_t& v, uint64_t min, uint64_t max) {
  checkWrite(name, v, min, max);
  traceValue(name, std::to_string(v));
  put(v, 4);
}

void ByteWriter::f64(const char* name, double& v) {
  uint64_t bits;
  std::memcpy(&bits, &v, 8);
  traceValue(name, formatDouble(v));
  put(bits, 8);
}

void ByteWriter::bytes(const char* name, std::vector<uint8_t>& v, size_t size) {
  if (size != v.size()) throw std::logic_error(std::string("writing ") + name + ": size mismatch");
  traceValue(name, std::to_string(size) + " bytes");
  data_.insert(data_.end(), v.begin(), v.end());
}

// ---- ByteReader ----

void ByteReader::fail(const std::string& what) const {
  throw Error(context_ + ", byte " + std::to_string(base_ + pos_) + ": " + what);
}

uint64_t ByteReader::get(const char* name, int size) {
  if (remaining() < static_cast<size_t>(size))
    fail(std::string("unit ends inside ") + name + " (" + std::to_string(remaining()) + " of " +
         std::to_string(size) + " bytes left)");
  uint64_t v = 0;
  for (int i = 0; i < size; ++i)
    v |= static_cast<uint64_t>(data_[pos_ + i]) << (8 * i);
  pos_ += size;
  return v;
}

void ByteReader::checkRange(const char* name, uint64_t v, uint64_t min, uint64_t max,
                            int size) const {
  // Named at the element's own offset (the reader has already moved past it).
  if (v < min || v > max)
    throw Error(context_ + ", byte " + std::to_string(base_ + pos_ - size) + ": " + name + " = " +
                std::to_string(v) + " out of range [" + std::to_string(min) + ", " +
                std::to_string(max) + "]");
}

void ByteReader::traceValue(const char* name, const std::string& value) {
  if (trace_) std::fprintf(trace_, "  %-32s = %s\n", name, value.c_str());
}

void ByteReader::u8(const char* name, uint8_t& v, uint64_t min, uint64_t max) {
  v = static_cast<uint8_t>(get(name, 1));
  traceValue(name, std::to_string(v));
  checkRange(name, v, min, max, 1);
}

void ByteReader::u16(const char* name, uint16_t& v, uint64_t min, uint64_t max) {
  v = static_cast<uint16_t>(get(name, 2));
  traceValue(name, std::to_string(v));
  checkRange(name, v, min, max, 2);
}

void ByteReader::u32(const char* name, uint32_t& v, uint64_t min, uint64_t max) {
  v = static_cast<uint32_t>(get(name, 4));
  traceValue(name, std::to_string(v));
  checkRange(name, v, min, max, 4);
}

void ByteReader::f64(const char* name, double& v) {
  uint64_t bits = get(name, 8);
  std::memcpy(&v, &bits, 8);
  traceValue(name, formatDouble(v));
}

void ByteReader::bytes(const char* name, std::vector<uint8_t>& v, size_t size) {
  if (remaining() < size)
    fail(std::string(name) + ": " + std::to_string(size) + " bytes declared, " +
         std::to_string(remaining()) + " left in the unit");
  v.assign(data_ + pos_, data_ + pos_ + size);
  pos_ += size;
  traceValue(name, std::to_string(size) + " bytes");
}

void ByteReader::expectEnd(const char* structure) const {
  if (remaining() != 0) fail(std::to_string(remaining()) + " unexpected bytes after " + structure);
}

}  // namespace tdvo
