// I-mesh decoding: a Draco mesh whose POSITION attribute holds the grid integers.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/mesh.h"

namespace tdvo {

// Decodes an I-mesh Draco payload into grid integers. The vertex order of the result is the
// order Draco's decoder produces; it is the vertex order of the whole GOM. `context` names the
// unit in error messages. Throws Error when the payload is not a valid Draco mesh, has no
// integer 3-component POSITION attribute, exceeds the vertex/triangle limits, or holds
// coordinates outside [0, 2^gridBits - 1].
IntMesh decodeIMesh(const std::vector<uint8_t>& payload, int gridBits, const std::string& context);

}  // namespace tdvo
