// P-mesh decoding: parses a P-mesh payload with the shared syntax (bitstream/pmesh_syntax.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "bitstream/pmesh_syntax.h"

namespace tdvo {

// Decodes the positions of a P mesh from `payload` given the previous decoded frame into
// `positions` (resized; must not be `previous`). `work` holds codePMesh's buffers: keep one per
// GOM so that decoding its frames allocates nothing. `context` names the unit in error
// messages; `trace` receives every syntax element.
void decodePMesh(const uint8_t* payload, size_t size, const GomTopology& topology,
                 const std::vector<Vec3i>& previous, const PMeshParams& params,
                 const std::string& context, PMeshWorkspace& work, std::vector<Vec3i>& positions,
                 std::FILE* trace = nullptr);

// Decodes an AFX-IC-style P mesh (codeTemporalDpcm) into `positions` (resized; not `previous`).
void decodeTemporalDpcm(const uint8_t* payload, size_t size, const std::vector<Vec3i>& previous,
                        const PMeshParams& params, const std::string& context,
                        std::vector<Vec3i>& positions, std::FILE* trace = nullptr);

// Convenience forms that return the positions (one allocation per call).
std::vector<Vec3i> decodePMesh(const std::vector<uint8_t>& payload, const GomTopology& topology,
                               const std::vector<Vec3i>& previous, const PMeshParams& params,
                               const std::string& context, std::FILE* trace = nullptr);
std::vector<Vec3i> decodeTemporalDpcm(const std::vector<uint8_t>& payload,
                                      const std::vector<Vec3i>& previous, const PMeshParams& params,
                                      const std::string& context, std::FILE* trace = nullptr);

}  // namespace tdvo
