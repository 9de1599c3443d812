// I-mesh decoding: a Draco mesh whose POSITION attribute holds the grid integers.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/core/mesh.h"
#include "decoder/draco_limits.h"

namespace tdvo {

// Decodes an I-mesh Draco payload into grid integers: Draco's values times `quantStep`
// (im_quant_step; each value at most (2^gridBits - 1) / quantStep). The vertex order of the result
// is the order Draco's decoder produces; it is the vertex order of the whole GOM. `context` names
// the unit in error messages. Throws Error when the payload is not a valid Draco mesh, has no
// integer 3-component POSITION attribute, exceeds the vertex/triangle limits, or holds a
// value outside [0, (2^gridBits - 1) / quantStep], or when its counts need more memory than the
// mesh-memory limit allows (draco_limits.h): `bytesRead` stream bytes read through this payload
// (0: the payload's size, for a payload decoded on its own), at most `memoryPerByte` bytes of
// decoding memory per byte (0: no limit).
IntMesh decodeIMesh(const std::vector<uint8_t>& payload, int gridBits, const std::string& context,
                    uint64_t bytesRead = 0, uint64_t memoryPerByte = kDefaultMaxMeshMemoryPerByte,
                    int quantStep = 1);

}  // namespace tdvo
