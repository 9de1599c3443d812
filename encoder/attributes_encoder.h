// Coding of an I mesh's texture coordinates and normals (the ATTRIBUTES unit,
// bitstream/attributes_syntax.h): the input's attributes taken into the I mesh's output order.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bitstream/attributes_syntax.h"
#include "common/core/mesh.h"
#include "encoder/imesh_encoder.h"

namespace tdvo {

struct AttributesEncoding {
  std::vector<uint8_t> payload;  // the ATTRIBUTES unit's payload (serialised AttributesUnit)
  DecodedAttributes decoded;     // what the decoder outputs with every frame of the I mesh
};

// The ATTRIBUTES unit of frame `frame` for `input` (the I mesh's input frame on the grid, with
// its attributes) coded as `i`. Texture coordinates and normals are coded per vertex when they
// are per vertex in the input (mesh_attributes.h), else per corner; `normals` kComputed codes
// none (the decoder computes them), kNone drops them; any other value codes the input's.
// `name` names the frame in errors (an output triangle without an input twin, whose corners'
// attributes are then unknown; more values than output corners). The payload is read back
// and checked (closed loop).
// `uvQuantBits` and `normalQuantBits` (0: exactly) quantise the values to multiples of
// 2^-bits (docs/bitstream.md, section 4.2); a value too large for that is an error.
AttributesEncoding encodeAttributes(const IntMesh& input, const IMeshEncoding& i, bool uvs,
                                    NormalMode normals, uint32_t frame, const std::string& name,
                                    int uvQuantBits = 0, int normalQuantBits = 0);

}  // namespace tdvo
