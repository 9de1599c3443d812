#include "decoder/pmesh_decoder.h"

namespace tdvo {

std::vector<Vec3i> decodePMesh(const std::vector<uint8_t>& payload, const GomTopology& topology,
                               const std::vector<Vec3i>& previous, const PMeshParams& params,
                               const std::string& context, std::FILE* trace) {
  CabacReaderIo io(payload.data(), payload.size(), context, trace);
  NoDecisions none;
  std::vector<Vec3i> positions = codePMesh(io, none, topology, previous, params);
  io.finish();
  return positions;
}

std::vector<Vec3i> decodeTemporalDpcm(const std::vector<uint8_t>& payload,
                                      const std::vector<Vec3i>& previous, const PMeshParams& params,
                                      const std::string& context, std::FILE* trace) {
  CabacReaderIo io(payload.data(), payload.size(), context, trace);
  NoDecisions none;
  std::vector<Vec3i> positions = codeTemporalDpcm(io, none, previous, params);
  io.finish();
  return positions;
}

}  // namespace tdvo
