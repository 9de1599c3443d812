// Fuzz target: PNG decoding (decodePng: libpng behind setjmp error handling, the size limits,
// palette / grey / 16-bit / tRNS / interlace conversions to 8 bits), plus a property check:
// what it decodes, encoded again with encodePng, decodes to the same image.
//
// The input is PNG bytes, decoded as they are and then with every chunk CRC repaired (libpng
// rejects a chunk whose CRC does not match, which would stop most mutations at the first
// chunk). Seeds: small PNGs of every channel count written by fuzz_make_corpus.
#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "common/core/error.h"
#include "common/media/png_io.h"
#include "common/views/image.h"
#include "fuzz/fuzz_support.h"

namespace {

// The PNG with the CRC of every complete chunk (length, type, data, CRC) recomputed.
std::vector<uint8_t> withValidChunkCrcs(std::vector<uint8_t> png) {
  size_t pos = 8;  // after the signature
  while (png.size() >= pos + 12) {
    const uint64_t length = uint64_t{png[pos]} << 24 | uint64_t{png[pos + 1]} << 16 |
                            uint64_t{png[pos + 2]} << 8 | png[pos + 3];
    if (length > png.size() - pos - 12) break;
    const uint32_t crc = static_cast<uint32_t>(
        crc32(crc32(0L, Z_NULL, 0), &png[pos + 4], static_cast<uInt>(4 + length)));
    const size_t at = pos + 8 + length;
    for (int i = 0; i < 4; ++i)
      png[at + i] = static_cast<uint8_t>(crc >> (24 - 8 * i));
    pos = at + 4;
  }
  return png;
}

void decode(const std::vector<uint8_t>& bytes) {
  tdvo::Image image;
  try {
    image = tdvo::decodePng(bytes, "fuzz.png");
  } catch (const tdvo::Error&) {
    return;
  }
  if (image.width == 0 || image.height == 0) return;
  if (tdvo::decodePng(tdvo::encodePng(image), "encoded.png") != image) {
    std::fprintf(stderr, "png fuzz target: encodePng output does not decode to the image\n");
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> bytes(data, data + size);
  decode(bytes);
  const std::vector<uint8_t> repaired = withValidChunkCrcs(bytes);
  if (repaired != bytes) decode(repaired);
  return 0;
}
