#include "bitstream/byte_io.h"

#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "common/core/error.h"
#include "common/core/number_text.h"

namespace tdvo {

namespace {

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
