#include "decoder/pmesh_decoder.h"

namespace tdvo {

void decodePMesh(const uint8_t* payload, size_t size, const GomTopology& topology,
                 const std::vector<Vec3i>& previous, const PMeshParams& params,
                 const std::string& context, PMeshWorkspace& work, std::vector<Vec3i>& positions,
                 std::FILE* trace) {
  CabacReaderIo io(payload, size, context, trace);
  NoDecisions none;
  codePMesh(io, none, topology, previous, params, work, positions);
  io.finish();
}

void decodeTemporalDpcm(const uint8_t* payload, size_t size, const std::vector<Vec3i>& previous,
                        const PMeshParams& params, const std::string& context,
                        std::vector<Vec3i>& positions, std::FILE* trace) {
  CabacReaderIo io(payload, size, context, trace);
  NoDecisions none;
  codeTemporalDpcm(io, none, previous, params, positions);
  io.finish();
}

std::vector<Vec3i> decodePMesh(const std::vector<uint8_t>& payload, const GomTopology& topology,
                               const std::vector<Vec3i>& previous, const PMeshParams& params,
                               const std::string& context, std::FILE* trace) {
  PMeshWorkspace work;
  std::vector<Vec3i> positions;
  decodePMesh(payload.data(), payload.size(), topology, previous, params, context, work, positions,
              trace);
  return positions;
}

std::vector<Vec3i> decodeTemporalDpcm(const std::vector<uint8_t>& payload,
                                      const std::vector<Vec3i>& previous, const PMeshParams& params,
                                      const std::string& context, std::FILE* trace) {
  std::vector<Vec3i> positions;
  decodeTemporalDpcm(payload.data(), payload.size(), previous, params, context, positions, trace);
  return positions;
}

}  // namespace tdvo
