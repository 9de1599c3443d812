// P-mesh decoding: parses a P-mesh payload with the shared syntax (bitstream/pmesh_syntax.h).
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "bitstream/pmesh_syntax.h"

namespace tdvo {

// Decodes the positions of a P mesh from `payload` given the previous decoded frame.
// `context` names the unit in error messages; `trace` receives every syntax element.
std::vector<Vec3i> decodePMesh(const std::vector<uint8_t>& payload, const GomTopology& topology,
                               const std::vector<Vec3i>& previous, const PMeshParams& params,
                               const std::string& context, std::FILE* trace = nullptr);

// Decodes an AFX-IC-style P mesh (codeTemporalDpcm).
std::vector<Vec3i> decodeTemporalDpcm(const std::vector<uint8_t>& payload,
                                      const std::vector<Vec3i>& previous, const PMeshParams& params,
                                      const std::string& context, std::FILE* trace = nullptr);

}  // namespace tdvo
