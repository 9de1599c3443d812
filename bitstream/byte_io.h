// Byte-level syntax I/O. Every syntax structure is written once, as a template function over
// the I/O direction:
//
//   template <class Io> void transfer(Io& io, GomHeader& gh) {
//     io.u32("gh_first_frame", gh.first_frame);
//     io.u16("gh_frame_count", gh.frame_count, 1, kMaxGomFrames);
//     ...
//   }
//
// With ByteWriter the fields are written; with ByteReader they are read into the struct. Both
// take the syntax element's name, which gives a syntax trace (--trace) and error messages that
// name the element. Ranges given to an element are checked on both sides: a writer that is
// handed an out-of-range value has a bug (std::logic_error); a reader that reads one has a
// corrupt stream (Error naming the unit, element, value and byte offset).
//
// Multi-byte values are little-endian. The reader never reads past its buffer: it throws.
#pragma once

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace tdvo {

class ByteWriter {
 public:
  static constexpr bool kReading = false;

  explicit ByteWriter(std::FILE* trace = nullptr) : trace_(trace) {}

  void u8(const char* name, uint8_t& v, uint64_t min = 0, uint64_t max = UINT8_MAX);
  void u16(const char* name, uint16_t& v, uint64_t min = 0, uint64_t max = UINT16_MAX);
  void u32(const char* name, uint32_t& v, uint64_t min = 0, uint64_t max = UINT32_MAX);
  void f64(const char* name, double& v);
  // `size` bytes; the size itself is coded by the caller (or is the rest of the unit).
  void bytes(const char* name, std::vector<uint8_t>& v, size_t size);
  // Everything up to the end of the unit.
  void rest(const char* name, std::vector<uint8_t>& v) { bytes(name, v, v.size()); }

  // A semantic condition on values just transferred; false is a bug on the writing side.
  void require(bool condition, const std::string& what) const {
    if (!condition) throw std::logic_error("writing: " + what);
  }

  const std::vector<uint8_t>& data() const { return data_; }
  std::vector<uint8_t> take() { return std::move(data_); }

 private:
  void put(uint64_t v, int size);
  void traceValue(const char* name, const std::string& value);
  std::FILE* trace_;
  std::vector<uint8_t> data_;
};

class ByteReader {
 public:
  static constexpr bool kReading = true;

  // `context` prefixes error messages, e.g. "unit 3 (I_MESH)"; `baseOffset` is the stream
  // offset of data[0], so that errors give absolute byte offsets.
  ByteReader(const uint8_t* data, size_t size, std::string context, uint64_t baseOffset,
             std::FILE* trace = nullptr)
      : data_(data), size_(size), context_(std::move(context)), base_(baseOffset), trace_(trace) {}

  void u8(const char* name, uint8_t& v, uint64_t min = 0, uint64_t max = UINT8_MAX);
  void u16(const char* name, uint16_t& v, uint64_t min = 0, uint64_t max = UINT16_MAX);
  void u32(const char* name, uint32_t& v, uint64_t min = 0, uint64_t max = UINT32_MAX);
  void f64(const char* name, double& v);
  void bytes(const char* name, std::vector<uint8_t>& v, size_t size);
  void rest(const char* name, std::vector<uint8_t>& v) { bytes(name, v, size_ - pos_); }

  // A semantic condition on values just read; false means a corrupt stream.
  void require(bool condition, const std::string& what) const {
    if (!condition) fail(what);
  }

  size_t position() const { return pos_; }
  size_t remaining() const { return size_ - pos_; }
  // Throws unless every byte of the unit was consumed (trailing garbage is an error).
  void expectEnd(const char* structure) const;
  // Throws Error "<context>, byte <offset>: <what>".
  [[noreturn]] void fail(const std::string& what) const;

 private:
  uint64_t get(const char* name, int size);
  void checkRange(const char* name, uint64_t v, uint64_t min, uint64_t max, int size) const;
  void traceValue(const char* name, const std::string& value);
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  std::string context_;
  uint64_t base_;
  std::FILE* trace_;
};

}  // namespace tdvo
