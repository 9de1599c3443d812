// The header hash line: what the per-frame MD5 lines do not cover. Frame lines hash grid
// integers, connectivity and YUV planes; the OBJ coordinates (origin + q * step), the PNG masks,
// the texture placement and dataset.json also depend on the sequence header (grid origin and
// step, frame rate, cameras). Encoder and decoder print
//
//   MD5 header=<32 lowercase hex digits>
//
// after the frame lines: the MD5 of the SEQUENCE_HEADER payload, as serialise() writes the parsed
// header (byte-identical to the payload of every stream the decoder accepts). docs/bitstream.md,
// section 8.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bitstream/syntax.h"

namespace tdvo {

std::string sequenceHeaderHashLine(const SequenceHeader& sh);

// The same line for a complete stream (its first unit, which must be the sequence header).
std::string sequenceHeaderHashLine(const std::vector<uint8_t>& stream, const std::string& name);

}  // namespace tdvo
