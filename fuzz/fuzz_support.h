// Shared pieces of the fuzz targets (docs/robustness.md).
//
// Every target defines libFuzzer's entry point, LLVMFuzzerTestOneInput. Built with TDVO_FUZZ
// (clang, -fsanitize=fuzzer) it becomes a fuzzer; built normally it is linked with
// replay_main.cpp into a plain executable that runs the files given on its command line, which
// is how ctest replays the seed corpus and every crash input kept in fuzz/regressions/.
//
// A target may throw tdvo::Error (the input was rejected, as it should be) and nothing else:
// any other exception, a crash, a sanitizer report, a hang or a huge allocation is a finding.
#pragma once

#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bitstream/units.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace tdvo {
namespace fuzz {

// A copy of a stream in which every unit that lies completely inside the data gets a correct
// unit_crc. A mutated payload would otherwise stop at the CRC check, so the targets that test
// what lies behind it (payload syntax, decoding) repair the CRCs first; the unit-container
// target also runs the raw input, CRCs as they are.
inline std::vector<uint8_t> withValidCrcs(const uint8_t* data, size_t size) {
  std::vector<uint8_t> out(data, data + size);
  size_t pos = sizeof kStreamMagic;
  while (size >= pos && size - pos >= kUnitOverhead) {
    const uint64_t payload = uint64_t{out[pos + 1]} | uint64_t{out[pos + 2]} << 8 |
                             uint64_t{out[pos + 3]} << 16 | uint64_t{out[pos + 4]} << 24;
    if (payload > size - pos - kUnitOverhead) break;
    uLong crc = crc32(0L, Z_NULL, 0);
    crc = crc32(crc, &out[pos], static_cast<uInt>(kUnitHeaderSize + payload));
    const size_t at = pos + kUnitHeaderSize + payload;
    for (int i = 0; i < 4; ++i)
      out[at + i] = static_cast<uint8_t>(crc >> (8 * i));
    pos = at + 4;
  }
  return out;
}

}  // namespace fuzz
}  // namespace tdvo
