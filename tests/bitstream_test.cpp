// The 3DVO byte-level syntax I/O, unit container and syntax structures (bitstream/): exact
// layouts, round trips, and errors (never reads past the end, never a huge allocation) on
// truncated, out-of-range and corrupted input.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "bitstream/byte_io.h"
#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/core/error.h"

// ---- Allocation watch: the largest single allocation made while a test runs a reader. ----
// operator new allocates with malloc, so operator delete is replaced too, to release with free
// (a replaced new paired with the library's delete is a mismatch AddressSanitizer reports).
namespace {
std::atomic<size_t> gLargestAllocation{0};
}  // namespace

__attribute__((noinline)) void* operator new(std::size_t size) {
  size_t seen = gLargestAllocation.load(std::memory_order_relaxed);
  while (size > seen && !gLargestAllocation.compare_exchange_weak(seen, size)) {
  }
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
__attribute__((noinline)) void operator delete(void* p) noexcept {
  std::free(p);
}
__attribute__((noinline)) void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace tdvo {
namespace {

// The Error message of `f()`; fails the test when no Error is thrown.
template <class F>
std::string errorOf(F f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no Error thrown";
  return "";
}

bool startsWith(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

// Serialises a structure with transfer().
template <class T>
std::vector<uint8_t> write(T value) {
  ByteWriter w;
  transfer(w, value);
  return w.take();
}

// Parses a structure from bytes as the decoder does (whole payload consumed).
template <class T>
T read(const std::vector<uint8_t>& bytes, const char* structure = "the structure") {
  ByteReader r(bytes.data(), bytes.size(), "s.3dvo: unit 1", 100);
  T value;
  transfer(r, value);
  r.expectEnd(structure);
  return value;
}

// ---- ByteWriter / ByteReader ----

TEST(ByteIo, LayoutIsLittleEndian) {
  ByteWriter w;
  uint8_t a = 0xAB;
  uint16_t b = 0x1234;
  uint32_t c = 0xDEADBEEF;
  double d = 1.0;  // 0x3FF0000000000000
  std::vector<uint8_t> e = {9, 8, 7};
  w.u8("a", a);
  w.u16("b", b);
  w.u32("c", c);
  w.f64("d", d);
  w.bytes("e", e, 3);
  const std::vector<uint8_t> expected = {0xAB, 0x34, 0x12, 0xEF, 0xBE, 0xAD, 0xDE, 0, 0,
                                         0,    0,    0,    0,    0xF0, 0x3F, 9,    8, 7};
  EXPECT_EQ(w.data(), expected);
}

TEST(ByteIo, RoundTripOfEveryElementKind) {
  const double doubles[] = {0.0,
                            -0.0,
                            1.5,
                            -1e-300,
                            1e300,
                            std::numeric_limits<double>::min(),
                            std::numeric_limits<double>::infinity(),
                            1.0 / 3.0};
  ByteWriter w;
  for (uint32_t i = 0; i < 8; ++i) {
    uint8_t a = static_cast<uint8_t>(i * 37 + (i == 7 ? 200 : 0));
    uint16_t b = static_cast<uint16_t>(i * 9001 + 1);
    uint32_t c = i == 7 ? UINT32_MAX : i * 0x01020304u;
    double d = doubles[i];
    std::vector<uint8_t> e(i, static_cast<uint8_t>(0xF0 + i));
    w.u8("a", a);
    w.u16("b", b);
    w.u32("c", c);
    w.f64("d", d);
    w.bytes("e", e, i);
  }
  std::vector<uint8_t> tail = {1, 2, 3, 4, 5};
  w.rest("tail", tail);
  const std::vector<uint8_t> bytes = w.take();

  ByteReader r(bytes.data(), bytes.size(), "ctx", 0);
  for (uint32_t i = 0; i < 8; ++i) {
    uint8_t a;
    uint16_t b;
    uint32_t c;
    double d;
    std::vector<uint8_t> e;
    r.u8("a", a);
    r.u16("b", b);
    r.u32("c", c);
    r.f64("d", d);
    r.bytes("e", e, i);
    EXPECT_EQ(a, static_cast<uint8_t>(i * 37 + (i == 7 ? 200 : 0)));
    EXPECT_EQ(b, static_cast<uint16_t>(i * 9001 + 1));
    EXPECT_EQ(c, i == 7 ? UINT32_MAX : i * 0x01020304u);
    EXPECT_EQ(std::memcmp(&d, &doubles[i], 8), 0) << i;
    EXPECT_EQ(e, std::vector<uint8_t>(i, static_cast<uint8_t>(0xF0 + i)));
  }
  EXPECT_EQ(r.remaining(), 5u);
  std::vector<uint8_t> back;
  r.rest("tail", back);
  EXPECT_EQ(back, tail);
  EXPECT_EQ(r.remaining(), 0u);
  EXPECT_EQ(r.position(), bytes.size());
  r.expectEnd("the test");
}

TEST(ByteIo, NanRoundTripsBitExactly) {
  ByteWriter w;
  uint64_t pattern = 0x7FF8000000001234ull;
  double nan;
  std::memcpy(&nan, &pattern, 8);
  w.f64("nan", nan);
  ByteReader r(w.data().data(), w.data().size(), "ctx", 0);
  double back;
  r.f64("nan", back);
  uint64_t backBits;
  std::memcpy(&backBits, &back, 8);
  EXPECT_EQ(backBits, pattern);
}

// A record of one of each element, then a truncation at every length: the reader throws with
// the element's name and its absolute byte offset, and never reads past the given size.
TEST(ByteIo, TruncationAtEveryLengthNamesElementAndOffset) {
  ByteWriter w;
  uint8_t a = 1;
  uint16_t b = 2;
  uint32_t c = 3;
  double d = 4;
  std::vector<uint8_t> e = {5, 6, 7};
  w.u8("elem_a", a);
  w.u16("elem_b", b);
  w.u32("elem_c", c);
  w.f64("elem_d", d);
  w.bytes("elem_e", e, 3);
  const std::vector<uint8_t> full = w.take();
  ASSERT_EQ(full.size(), 18u);
  struct Element {
    const char* name;
    size_t start, size;
  };
  const Element layout[] = {
      {"elem_a", 0, 1}, {"elem_b", 1, 2}, {"elem_c", 3, 4}, {"elem_d", 7, 8}, {"elem_e", 15, 3}};
  const uint64_t base = 1000;
  for (size_t length = 0; length < full.size(); ++length) {
    // The bytes beyond `length` exist in memory but must never be looked at: make them
    // different so that a reader peeking past the end could not pass unnoticed.
    std::vector<uint8_t> buffer = full;
    for (size_t i = length; i < buffer.size(); ++i)
      buffer[i] ^= 0xFF;
    ByteReader r(buffer.data(), length, "s.3dvo: unit 4 (GOM_HEADER) at byte 995", base);
    const std::string message = errorOf([&] {
      uint8_t a2;
      uint16_t b2;
      uint32_t c2;
      double d2;
      std::vector<uint8_t> e2;
      r.u8("elem_a", a2);
      r.u16("elem_b", b2);
      r.u32("elem_c", c2);
      r.f64("elem_d", d2);
      r.bytes("elem_e", e2, 3);
      EXPECT_EQ(a2, a);
      EXPECT_EQ(b2, b);
      EXPECT_EQ(c2, c);
      EXPECT_EQ(d2, d);
    });
    const Element* cut = nullptr;
    for (const Element& el : layout)
      if (length < el.start + el.size) {
        cut = &el;
        break;
      }
    ASSERT_NE(cut, nullptr);
    const std::string prefix =
        "s.3dvo: unit 4 (GOM_HEADER) at byte 995, byte " + std::to_string(base + cut->start) + ": ";
    const std::string left = std::to_string(length - cut->start);
    const std::string expected =
        cut->size == 3 && std::string(cut->name) == "elem_e"
            ? prefix + "elem_e: 3 bytes declared, " + left + " left in the unit"
            : prefix + "unit ends inside " + cut->name + " (" + left + " of " +
                  std::to_string(cut->size) + " bytes left)";
    EXPECT_EQ(message, expected) << "length " << length;
    EXPECT_EQ(r.position(), cut->start);
  }
}

TEST(ByteIo, ReadRangeViolationsNameElementValueAndOffset) {
  const std::vector<uint8_t> bytes = {7, 0x00, 0x01, 0x05, 0, 0, 0};
  ByteReader r(bytes.data(), bytes.size(), "ctx", 50);
  uint8_t a;
  uint16_t b;
  uint32_t c;
  EXPECT_EQ(errorOf([&] { r.u8("x_bits", a, 8, 20); }),
            "ctx, byte 50: x_bits = 7 out of range [8, 20]");
  EXPECT_EQ(errorOf([&] { r.u16("x_count", b, 1, 255); }),
            "ctx, byte 51: x_count = 256 out of range [1, 255]");
  EXPECT_EQ(errorOf([&] { r.u32("x_frame", c, 6, 9); }),
            "ctx, byte 53: x_frame = 5 out of range [6, 9]");
  // Limits are inclusive.
  ByteReader ok(bytes.data(), bytes.size(), "ctx", 50);
  ok.u8("x_bits", a, 7, 7);
  ok.u16("x_count", b, 256, 256);
  ok.u32("x_frame", c, 5, 5);
  EXPECT_EQ(a, 7);
  EXPECT_EQ(b, 256);
  EXPECT_EQ(c, 5u);
}

TEST(ByteIo, WriterRejectsOutOfRangeValues) {
  ByteWriter w;
  uint8_t a = 21;
  uint16_t b = 0;
  uint32_t c = 10;
  std::vector<uint8_t> e = {1, 2};
  EXPECT_THROW(w.u8("x_bits", a, 8, 20), std::logic_error);
  EXPECT_THROW(w.u16("x_count", b, 1, 10), std::logic_error);
  EXPECT_THROW(w.u32("x_frame", c, 0, 9), std::logic_error);
  EXPECT_THROW(w.bytes("x_data", e, 3), std::logic_error);
  EXPECT_THROW(w.require(false, "a rule"), std::logic_error);
  EXPECT_TRUE(w.data().empty());  // nothing was written for rejected values
}

TEST(ByteIo, ExpectEndAndRequire) {
  const std::vector<uint8_t> bytes = {1, 2, 3, 4};
  ByteReader r(bytes.data(), bytes.size(), "s.3dvo: unit 2 (GOM_HEADER) at byte 60", 65);
  uint8_t a;
  r.u8("a", a);
  EXPECT_EQ(errorOf([&] { r.expectEnd("the GOM header"); }),
            "s.3dvo: unit 2 (GOM_HEADER) at byte 60, byte 66: 3 unexpected bytes after the GOM "
            "header");
  EXPECT_EQ(errorOf([&] { r.require(false, "gh_rule shall hold"); }),
            "s.3dvo: unit 2 (GOM_HEADER) at byte 60, byte 66: gh_rule shall hold");
  r.require(true, "fine");
  std::vector<uint8_t> rest;
  r.rest("rest", rest);
  r.expectEnd("the GOM header");
  EXPECT_EQ(rest, (std::vector<uint8_t>{2, 3, 4}));
}

TEST(ByteIo, HugeDeclaredSizeDoesNotAllocate) {
  const std::vector<uint8_t> bytes(16, 0);
  ByteReader r(bytes.data(), bytes.size(), "ctx", 0);
  std::vector<uint8_t> v;
  gLargestAllocation = 0;
  const std::string message = errorOf([&] { r.bytes("payload", v, size_t{1} << 40); });
  EXPECT_LT(gLargestAllocation.load(), size_t{1} << 20);
  EXPECT_EQ(message, "ctx, byte 0: payload: 1099511627776 bytes declared, 16 left in the unit");
}

TEST(ByteIo, TraceNamesEveryElement) {
  std::FILE* trace = std::tmpfile();
  ASSERT_NE(trace, nullptr);
  ByteWriter w(trace);
  uint8_t a = 3;
  uint32_t b = 70000;
  double c = 0.5;
  std::vector<uint8_t> d = {1, 2};
  w.u8("sh_a", a);
  w.u32("sh_b", b);
  w.f64("sh_c", c);
  w.bytes("sh_d", d, 2);
  ByteReader r(w.data().data(), w.data().size(), "ctx", 0, trace);
  r.u8("sh_a", a);
  r.u32("sh_b", b);
  r.f64("sh_c", c);
  r.bytes("sh_d", d, 2);
  std::rewind(trace);
  std::string text;
  char buffer[256];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, trace)) > 0)
    text.append(buffer, n);
  std::fclose(trace);
  const std::string one =
      "  sh_a                             = 3\n"
      "  sh_b                             = 70000\n"
      "  sh_c                             = 0.5\n"
      "  sh_d                             = 2 bytes\n";
  EXPECT_EQ(text, one + one);
}

// ---- Unit container ----

std::vector<uint8_t> payloadOf(size_t size, uint8_t seed) {
  std::vector<uint8_t> p(size);
  for (size_t i = 0; i < size; ++i)
    p[i] = static_cast<uint8_t>(seed + i * 31);
  return p;
}

struct ReadUnit {
  uint8_t type;
  std::vector<uint8_t> payload;
  uint64_t offset, payloadOffset;
  size_t index;
};

std::vector<ReadUnit> readAll(const std::vector<uint8_t>& stream, size_t size,
                              const std::string& name = "s.3dvo") {
  UnitReader reader(stream.data(), size, name);
  std::vector<ReadUnit> units;
  UnitView view;
  while (reader.next(view))
    units.push_back({view.type, std::vector<uint8_t>(view.payload, view.payload + view.size),
                     view.offset, view.payloadOffset, view.index});
  return units;
}

// Four units: 0, 1, 7 and 20 payload bytes.
std::vector<uint8_t> smallStream(UnitWriter& writer) {
  writer.write(UnitType::kSequenceHeader, payloadOf(20, 1));
  writer.write(UnitType::kGomHeader, payloadOf(7, 2));
  writer.write(UnitType::kIMesh, {});
  writer.write(UnitType::kPMesh, payloadOf(1, 3));
  return writer.bytes();
}

TEST(Units, LayoutAndCrc) {
  UnitWriter writer;
  EXPECT_EQ(writer.bytes(), (std::vector<uint8_t>{'3', 'D', 'V', 'O'}));
  const std::vector<uint8_t> payload = {0x10, 0x20, 0x30};
  writer.write(UnitType::kGomHeader, payload);
  const std::vector<uint8_t>& s = writer.bytes();
  ASSERT_EQ(s.size(), 4 + kUnitOverhead + 3);
  EXPECT_EQ(s[4], 2);  // GOM_HEADER
  EXPECT_EQ((std::vector<uint8_t>(s.begin() + 5, s.begin() + 9)),
            (std::vector<uint8_t>{3, 0, 0, 0}));
  EXPECT_EQ((std::vector<uint8_t>(s.begin() + 9, s.begin() + 12)), payload);
  const uint32_t crc = static_cast<uint32_t>(crc32(0L, s.data() + 4, 8));
  EXPECT_EQ(
      (std::vector<uint8_t>(s.begin() + 12, s.end())),
      (std::vector<uint8_t>{static_cast<uint8_t>(crc), static_cast<uint8_t>(crc >> 8),
                            static_cast<uint8_t>(crc >> 16), static_cast<uint8_t>(crc >> 24)}));
  EXPECT_EQ(writer.bytesOfType(UnitType::kGomHeader), kUnitOverhead + 3);
  EXPECT_EQ(writer.bytesOfType(UnitType::kIMesh), 0u);
}

TEST(Units, RoundTrip) {
  UnitWriter writer;
  const std::vector<uint8_t> stream = smallStream(writer);
  const std::vector<ReadUnit> units = readAll(stream, stream.size());
  ASSERT_EQ(units.size(), 4u);
  const uint8_t types[] = {1, 2, 3, 4};
  const std::vector<uint8_t> payloads[] = {payloadOf(20, 1), payloadOf(7, 2), {}, payloadOf(1, 3)};
  uint64_t offset = 4;
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(units[i].type, types[i]);
    EXPECT_EQ(units[i].payload, payloads[i]);
    EXPECT_EQ(units[i].index, i);
    EXPECT_EQ(units[i].offset, offset);
    EXPECT_EQ(units[i].payloadOffset, offset + kUnitHeaderSize);
    offset += kUnitOverhead + payloads[i].size();
  }
  EXPECT_EQ(offset, stream.size());
  EXPECT_EQ(writer.bytesOfType(UnitType::kSequenceHeader), kUnitOverhead + 20);
  EXPECT_EQ(writer.bytesOfType(UnitType::kPMesh), kUnitOverhead + 1);
  // A stream of just the magic has no units.
  EXPECT_TRUE(readAll(UnitWriter().bytes(), 4).empty());
}

TEST(Units, Describe) {
  UnitView v;
  v.type = 3;
  v.index = 3;
  v.offset = 1234;
  EXPECT_EQ(v.describe(), "unit 3 (I_MESH) at byte 1234");
  v.type = 99;
  EXPECT_EQ(v.describe(), "unit 3 (unknown type) at byte 1234");
  EXPECT_STREQ(unitTypeName(1), "SEQUENCE_HEADER");
  EXPECT_STREQ(unitTypeName(2), "GOM_HEADER");
  EXPECT_STREQ(unitTypeName(4), "P_MESH");
}

TEST(Units, NotA3dvoStream) {
  const std::vector<uint8_t> other = {'R', 'I', 'F', 'F', 0, 0, 0, 0};
  EXPECT_EQ(errorOf([&] { readAll(other, other.size(), "x.wav"); }),
            "x.wav: not a 3DVO stream (the first four bytes are not \"3DVO\")");
  const std::vector<uint8_t> shortStream = {'3', 'D'};
  EXPECT_EQ(errorOf([&] { readAll(shortStream, shortStream.size(), "x"); }),
            "x: not a 3DVO stream (the first four bytes are not \"3DVO\")");
  EXPECT_EQ(errorOf([&] { readAll(shortStream, 0, "x"); }),
            "x: not a 3DVO stream (the first four bytes are not \"3DVO\")");
}

TEST(Units, CrcCatchesEveryFlippedBit) {
  UnitWriter writer;
  const std::vector<uint8_t> stream = smallStream(writer);
  for (size_t position = 0; position < stream.size(); ++position)
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<uint8_t> bad = stream;
      bad[position] ^= static_cast<uint8_t>(1u << bit);
      const std::string message = errorOf([&] { readAll(bad, bad.size()); });
      if (position < 4) {
        EXPECT_TRUE(startsWith(message, "s.3dvo: not a 3DVO stream")) << message;
      } else {
        EXPECT_TRUE(startsWith(message, "s.3dvo: unit ")) << message;
      }
    }
}

TEST(Units, CrcCatchesEveryFlippedByte) {
  UnitWriter writer;
  const std::vector<uint8_t> stream = smallStream(writer);
  for (size_t position = 4; position < stream.size(); ++position)
    for (int value : {0x00, 0xFF, 0x5A}) {
      std::vector<uint8_t> bad = stream;
      if (bad[position] == value) continue;
      bad[position] = static_cast<uint8_t>(value);
      const std::string message = errorOf([&] { readAll(bad, bad.size()); });
      EXPECT_TRUE(startsWith(message, "s.3dvo: unit ")) << message;
    }
}

TEST(Units, CorruptedPayloadNamesTheUnit) {
  UnitWriter writer;
  std::vector<uint8_t> stream = smallStream(writer);
  const size_t secondUnit = 4 + kUnitOverhead + 20;
  stream[secondUnit + kUnitHeaderSize + 3] ^= 0x10;
  EXPECT_EQ(errorOf([&] { readAll(stream, stream.size()); }),
            "s.3dvo: unit 1 (GOM_HEADER) at byte " + std::to_string(secondUnit) +
                ": CRC mismatch (corrupted stream)");
}

TEST(Units, TruncationAtEveryLength) {
  UnitWriter writer;
  const std::vector<uint8_t> stream = smallStream(writer);
  std::vector<size_t> boundaries = {4};
  for (size_t payload : {20, 7, 0, 1})
    boundaries.push_back(boundaries.back() + kUnitOverhead + payload);
  for (size_t length = 0; length < stream.size(); ++length) {
    const bool atBoundary =
        std::find(boundaries.begin(), boundaries.end(), length) != boundaries.end();
    if (atBoundary) {
      // The container alone cannot tell a stream cut between units from a shorter stream: it
      // returns the complete units (the stream decoder then misses a frame; see
      // roundtrip_test).
      const size_t complete =
          std::find(boundaries.begin(), boundaries.end(), length) - boundaries.begin();
      EXPECT_EQ(readAll(stream, length).size(), complete);
      continue;
    }
    const std::string message = errorOf([&] { readAll(stream, length); });
    if (length < 4)
      EXPECT_TRUE(startsWith(message, "s.3dvo: not a 3DVO stream")) << message;
    else
      EXPECT_TRUE(message.find("truncated") != std::string::npos &&
                  startsWith(message, "s.3dvo: unit "))
          << "length " << length << ": " << message;
  }
}

std::vector<uint8_t> streamWithUnitSize(uint32_t size, size_t actualPayload) {
  std::vector<uint8_t> s = {'3', 'D', 'V', 'O', 3};
  for (int i = 0; i < 4; ++i)
    s.push_back(static_cast<uint8_t>(size >> (8 * i)));
  s.resize(s.size() + actualPayload + 4, 0);
  return s;
}

TEST(Units, HugeUnitSizeDoesNotAllocate) {
  for (uint32_t size : {UINT32_MAX, kMaxUnitSize + 1, kMaxUnitSize, 1000000u}) {
    const std::vector<uint8_t> s = streamWithUnitSize(size, 100);
    gLargestAllocation = 0;
    const std::string message = errorOf([&] {
      UnitReader reader(s.data(), s.size(), "s.3dvo");
      UnitView view;
      reader.next(view);
    });
    EXPECT_LT(gLargestAllocation.load(), size_t{1} << 16) << size;
    const std::string prefix =
        "s.3dvo: unit 0 (I_MESH) at byte 4: unit_size " + std::to_string(size);
    if (size > kMaxUnitSize)
      EXPECT_EQ(message, prefix + " exceeds the 1 GiB limit");
    else
      EXPECT_EQ(message, prefix +
                             " runs past the end of the stream (truncated or corrupted "
                             "stream)");
  }
}

TEST(Units, TrailingBytesAfterTheLastUnit) {
  UnitWriter writer;
  std::vector<uint8_t> stream = smallStream(writer);
  stream.push_back(1);
  stream.push_back(2);
  const std::string message = errorOf([&] { readAll(stream, stream.size()); });
  EXPECT_EQ(message, "s.3dvo: unit 4 at byte " + std::to_string(stream.size() - 2) +
                         ": stream ends inside the unit header (truncated stream)");
}

// ---- Syntax structures ----

TEST(Syntax, SequenceHeaderRoundTrip) {
  SequenceHeader sh;
  sh.sh_frame_count = 48;
  sh.sh_frame_rate = 29.97;
  sh.sh_grid_bits = 17;
  sh.sh_grid_origin[0] = -1.25;
  sh.sh_grid_origin[1] = 1.0 / 3.0;
  sh.sh_grid_origin[2] = 1e6;
  sh.sh_grid_step = 0.000123;
  sh.sh_first_frame = 1000000000;
  const std::vector<uint8_t> bytes = write(sh);
  // ... + sh_attributes_present + sh_num_cameras
  EXPECT_EQ(bytes.size(), 2u + 4 + 4 + 8 + 1 + 3 * 8 + 8 + 1 + 2);
  EXPECT_EQ(bytes[0], kSyntaxVersion & 0xFF);
  EXPECT_EQ(bytes[18], 17);  // sh_grid_bits after version, first frame, frame count and rate
  const SequenceHeader back = read<SequenceHeader>(bytes);
  EXPECT_EQ(back.sh_syntax_version, kSyntaxVersion);
  EXPECT_EQ(back.sh_first_frame, 1000000000u);
  EXPECT_EQ(back.sh_frame_count, 48u);
  EXPECT_EQ(back.sh_frame_rate, 29.97);
  EXPECT_EQ(back.sh_grid_bits, 17);
  EXPECT_EQ(back.sh_grid_origin[0], -1.25);
  EXPECT_EQ(back.sh_grid_origin[1], 1.0 / 3.0);
  EXPECT_EQ(back.sh_grid_origin[2], 1e6);
  EXPECT_EQ(back.sh_grid_step, 0.000123);
}

TEST(Syntax, GomHeaderRoundTrip) {
  GomHeader gh;
  gh.gh_first_frame = 960;
  gh.gh_frame_count = 48;
  gh.gh_pmesh_mode = static_cast<uint8_t>(PMeshMode::kIntra);
  const std::vector<uint8_t> bytes = write(gh);
  EXPECT_EQ(bytes, (std::vector<uint8_t>{0xC0, 0x03, 0, 0, 48, 0, 0}));
  const GomHeader back = read<GomHeader>(bytes);
  EXPECT_EQ(back.gh_first_frame, 960u);
  EXPECT_EQ(back.gh_frame_count, 48);
  EXPECT_EQ(back.gh_pmesh_mode, 0);
}

TEST(Syntax, IMeshAndPMeshUnitRoundTrip) {
  IMeshUnit im;
  im.im_frame = 7;
  im.im_quant_step = 0x0203;
  im.im_draco_payload = payloadOf(300, 5);
  std::vector<uint8_t> bytes = write(im);
  ASSERT_EQ(bytes.size(), 306u);
  EXPECT_EQ(bytes[0], 7);
  EXPECT_EQ(bytes[4], 0x03);  // im_quant_step, u16 little-endian, after im_frame
  EXPECT_EQ(bytes[5], 0x02);
  IMeshUnit imBack = read<IMeshUnit>(bytes);
  EXPECT_EQ(imBack.im_frame, 7u);
  EXPECT_EQ(imBack.im_quant_step, 0x0203);
  EXPECT_EQ(imBack.im_draco_payload, im.im_draco_payload);
  // Before syntax version 5 there is no im_quant_step: it is 1 and the payload follows im_frame.
  IMeshUnit v4;
  v4.syntaxVersion = 4;
  v4.im_quant_step = 9;  // not written
  v4.im_frame = 7;
  v4.im_draco_payload = im.im_draco_payload;
  bytes = write(v4);
  ASSERT_EQ(bytes.size(), 304u);
  IMeshUnit v4Back;
  v4Back.syntaxVersion = 4;
  ByteReader reader(bytes.data(), bytes.size(), "v4", 0);
  transfer(reader, v4Back);
  EXPECT_EQ(v4Back.im_quant_step, 1);
  EXPECT_EQ(v4Back.im_draco_payload, im.im_draco_payload);
  // Its range: 1 .. 4096.
  for (uint16_t step : {0, 4097}) {
    std::vector<uint8_t> bad = write(im);
    bad[4] = static_cast<uint8_t>(step & 0xFF);
    bad[5] = static_cast<uint8_t>(step >> 8);
    EXPECT_NE(errorOf([&] { read<IMeshUnit>(bad); }).find("im_quant_step"), std::string::npos);
  }

  PMeshUnit pm;
  pm.pm_frame = 123456;
  pm.pm_cabac_payload = payloadOf(3, 9);
  bytes = write(pm);
  EXPECT_EQ(bytes, (std::vector<uint8_t>{0x40, 0xE2, 0x01, 0, 9, 40, 71}));
  PMeshUnit pmBack = read<PMeshUnit>(bytes);
  EXPECT_EQ(pmBack.pm_frame, 123456u);
  EXPECT_EQ(pmBack.pm_cabac_payload, pm.pm_cabac_payload);

  // An empty payload is representable (the decoder of the payload rejects it).
  pm.pm_cabac_payload.clear();
  EXPECT_TRUE(read<PMeshUnit>(write(pm)).pm_cabac_payload.empty());
}

// A valid sequence header (the default one has sh_frame_count 0, which is out of range).
SequenceHeader validSequenceHeader() {
  SequenceHeader sh;
  sh.sh_frame_count = 1;
  return sh;
}

// Patches one element of a serialised sequence header and returns the parse error.
std::string sequenceHeaderError(size_t offset, const std::vector<uint8_t>& value) {
  std::vector<uint8_t> bytes = write(validSequenceHeader());
  std::copy(value.begin(), value.end(), bytes.begin() + offset);
  return errorOf([&] { read<SequenceHeader>(bytes); });
}

std::vector<uint8_t> le64(double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, 8);
  std::vector<uint8_t> out;
  for (int i = 0; i < 8; ++i)
    out.push_back(static_cast<uint8_t>(bits >> (8 * i)));
  return out;
}

TEST(Syntax, SequenceHeaderLimits) {
  const std::string at = "s.3dvo: unit 1, byte ";
  EXPECT_EQ(sequenceHeaderError(0, {1, 0}),
            at + "102: sh_syntax_version 1 is not supported (this decoder reads versions 2 to " +
                std::to_string(kSyntaxVersion) + ")");
  EXPECT_EQ(sequenceHeaderError(51, {2}),
            at + "151: sh_attributes_present = 2 out of range [0, 1]");
  EXPECT_EQ(sequenceHeaderError(2, {0x01, 0xCA, 0x9A, 0x3B}),  // 10^9 + 1
            at + "102: sh_first_frame = 1000000001 out of range [0, 1000000000]");
  EXPECT_EQ(sequenceHeaderError(6, {0, 0, 0, 0}),
            at + "106: sh_frame_count = 0 out of range [1, " + std::to_string(kMaxFrames) + "]");
  EXPECT_EQ(
      sequenceHeaderError(6, {0xFF, 0xFF, 0xFF, 0xFF}),
      at + "106: sh_frame_count = 4294967295 out of range [1, " + std::to_string(kMaxFrames) + "]");
  for (double rate : {0.0, -25.0, 1000.5, std::nan(""), HUGE_VAL})
    EXPECT_EQ(sequenceHeaderError(10, le64(rate)), at + "118: sh_frame_rate must be in (0, 1000]")
        << rate;
  EXPECT_EQ(sequenceHeaderError(18, {7}), at + "118: sh_grid_bits = 7 out of range [8, 20]");
  EXPECT_EQ(sequenceHeaderError(18, {21}), at + "118: sh_grid_bits = 21 out of range [8, 20]");
  EXPECT_EQ(sequenceHeaderError(27, le64(std::nan(""))), at + "151: sh_grid_origin must be finite");
  EXPECT_EQ(sequenceHeaderError(35, le64(-HUGE_VAL)), at + "151: sh_grid_origin must be finite");
  for (double step : {0.0, -1.0, std::nan(""), HUGE_VAL})
    EXPECT_EQ(sequenceHeaderError(43, le64(step)),
              at + "151: sh_grid_step must be finite and positive")
        << step;
}

TEST(Syntax, GomHeaderLimits) {
  auto error = [](std::vector<uint8_t> bytes) {
    return errorOf([&] { read<GomHeader>(bytes, "the GOM header"); });
  };
  const std::string at = "s.3dvo: unit 1, byte ";
  EXPECT_EQ(error({0x40, 0x42, 0x0F, 0, 1, 0, 0}),
            at + "100: gh_first_frame = 1000000 out of range [0, 999999]");
  EXPECT_EQ(error({0, 0, 0, 0, 0, 0, 0}), at + "104: gh_frame_count = 0 out of range [1, 65535]");
  EXPECT_EQ(
      error({0, 0, 0, 0, 1, 0, 0xFF}).rfind(at + "106: gh_pmesh_mode = 255 out of range [0, ", 0),
      0u);
  EXPECT_EQ(error({0, 0, 0, 0, 1, 0, 0, 0}), at + "107: 1 unexpected bytes after the GOM header");
  EXPECT_EQ(error({0, 0, 0, 0, 1, 0}),
            at + "106: unit ends inside gh_pmesh_mode (0 of 1 bytes left)");
}

TEST(Syntax, FrameNumberLimits) {
  const std::vector<uint8_t> bytes = {0x40, 0x42, 0x0F, 0, 1, 2, 3};
  EXPECT_EQ(errorOf([&] { read<IMeshUnit>(bytes); }),
            "s.3dvo: unit 1, byte 100: im_frame = 1000000 out of range [0, 999999]");
  EXPECT_EQ(errorOf([&] { read<PMeshUnit>(bytes); }),
            "s.3dvo: unit 1, byte 100: pm_frame = 1000000 out of range [0, 999999]");
  EXPECT_EQ(errorOf([&] {
              read<IMeshUnit>(std::vector<uint8_t>{1, 0, 0});
            }),
            "s.3dvo: unit 1, byte 100: unit ends inside im_frame (3 of 4 bytes left)");
}

TEST(Syntax, SequenceHeaderTruncatedAtEveryLength) {
  const std::vector<uint8_t> bytes = write(validSequenceHeader());
  const struct {
    const char* name;
    size_t start, size;
  } layout[] = {{"sh_syntax_version", 0, 2}, {"sh_first_frame", 2, 4},
                {"sh_frame_count", 6, 4},    {"sh_frame_rate", 10, 8},
                {"sh_grid_bits", 18, 1},     {"sh_grid_origin_x", 19, 8},
                {"sh_grid_origin_y", 27, 8}, {"sh_grid_origin_z", 35, 8},
                {"sh_grid_step", 43, 8},     {"sh_attributes_present", 51, 1}};
  for (size_t length = 0; length < bytes.size(); ++length) {
    const std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + length);
    const std::string message = errorOf([&] { read<SequenceHeader>(cut); });
    for (const auto& el : layout)
      if (length < el.start + el.size) {
        EXPECT_EQ(message, "s.3dvo: unit 1, byte " + std::to_string(100 + el.start) +
                               ": unit ends inside " + el.name + " (" +
                               std::to_string(length - el.start) + " of " +
                               std::to_string(el.size) + " bytes left)");
        break;
      }
  }
}

// Version 2 headers are read too: they have no sh_attributes_present (read as 0) and
// serialise again as version 2 (the header hash of a version 2 stream is unchanged).
TEST(Syntax, Version2SequenceHeaderIsRead) {
  SequenceHeader sh = validSequenceHeader();
  sh.sh_attributes_present = 1;
  const std::vector<uint8_t> v3 = write(sh);
  sh.sh_syntax_version = 2;
  const std::vector<uint8_t> v2 = write(sh);
  ASSERT_EQ(v2.size() + 1, v3.size());
  const SequenceHeader back = read<SequenceHeader>(v2);
  EXPECT_EQ(back.sh_syntax_version, 2);
  EXPECT_EQ(back.sh_attributes_present, 0);
  EXPECT_EQ(write(back), v2);
  EXPECT_EQ(read<SequenceHeader>(v3).sh_attributes_present, 1);
}

// The input dataset's fields travel with the cameras (issue 17.3): names, description, up.
TEST(Syntax, SequenceHeaderCarriesTheDatasetFields) {
  SequenceHeader sh = validSequenceHeader();
  sh.cameras.resize(2);
  for (CameraParameters& c : sh.cameras)
    c.cam_width = c.cam_height = 64;
  sh.cameras[0].cam_name = "left \xC3\xA9";  // UTF-8
  sh.cameras[1].cam_name = "right";
  sh.sh_description = "two cameras";
  sh.sh_up_present = 1;
  sh.sh_up[0] = 0;
  sh.sh_up[1] = 0;
  sh.sh_up[2] = -1;
  const SequenceHeader back = read<SequenceHeader>(write(sh));
  ASSERT_EQ(back.cameras.size(), 2u);
  EXPECT_EQ(back.cameras[0].cam_name, "left \xC3\xA9");
  EXPECT_EQ(back.cameras[1].cam_name, "right");
  EXPECT_EQ(back.sh_description, "two cameras");
  EXPECT_EQ(back.sh_up_present, 1);
  EXPECT_EQ(back.sh_up[2], -1.0);
  sh.sh_up_present = 0;
  EXPECT_EQ(read<SequenceHeader>(write(sh)).sh_up_present, 0);

  // What the writer refuses and a decoder too: an empty name, two cameras of one name, text
  // that is not UTF-8 (or holds NUL), a zero up.
  SequenceHeader same = sh;
  same.cameras[1].cam_name = same.cameras[0].cam_name;
  EXPECT_THROW(write(same), std::logic_error);
  for (const std::string& text : {std::string("a\xFF"), std::string("a\0b", 3),
                                  std::string("\xC0\x80"), std::string("\xED\xA0\x80")}) {
    SequenceHeader invalid = sh;
    invalid.sh_description = text;
    EXPECT_THROW(write(invalid), std::logic_error);
  }
  // The reader checks the same: patch the bytes of a valid header.
  std::vector<uint8_t> bytes = write(sh);
  const size_t nameAt = 54 + 2;  // the first camera's cam_name bytes
  ASSERT_EQ(bytes[nameAt], 'l');
  bytes[nameAt] = 0xFF;
  const std::string badText = errorOf([&] { read<SequenceHeader>(bytes); });
  EXPECT_NE(badText.find("cam_name must be UTF-8 text without NUL bytes"), std::string::npos)
      << badText;
  bytes = write(sh);
  bytes[nameAt - 2] = 0;  // cam_name_length 0
  const std::string empty = errorOf([&] { read<SequenceHeader>(bytes); });
  EXPECT_NE(empty.find("cam_name_length = 0 out of range [1, 255]"), std::string::npos) << empty;
  SequenceHeader zeroUp = sh;
  zeroUp.sh_up_present = 1;
  zeroUp.sh_up[2] = 0;
  EXPECT_THROW(write(zeroUp), std::logic_error);
}

TEST(Syntax, WriterChecksTheSameLimits) {
  SequenceHeader sh = validSequenceHeader();
  EXPECT_NO_THROW(write(sh));
  sh.sh_grid_bits = 21;
  EXPECT_THROW(write(sh), std::logic_error);
  sh = validSequenceHeader();
  sh.sh_frame_count = 0;
  EXPECT_THROW(write(sh), std::logic_error);
  sh = validSequenceHeader();
  sh.sh_grid_step = 0;
  EXPECT_THROW(write(sh), std::logic_error);
  GomHeader gh;
  gh.gh_frame_count = 0;
  EXPECT_THROW(write(gh), std::logic_error);
}

}  // namespace
}  // namespace tdvo
