// Fuzz target: the checks made on a Draco payload before Draco sees it (decoder/draco_limits.h):
// the header and connectivity counts (checkDracoMeshCounts, then the mesh-memory limit
// checkDracoMemory with the payload's size, as decodeIMesh does), the attribute descriptors
// (checkDracoAttributeDescriptors, on its own and where Draco's decoder reaches them in
// decodeCheckedDracoMesh), and Draco's decoding behind them.
//
// The input is an im_draco_payload. Its first byte also selects the descriptor parser's mode
// (bit 0: Edgebreaker) for the direct call on the rest of the input. Seeds: the I-mesh payloads
// of the conformance streams.
#include <cstdint>
#include <vector>

#include <draco/mesh/mesh.h>

#include "common/core/error.h"
#include "decoder/draco_limits.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 0) tdvo::checkDracoAttributeDescriptors(data + 1, size - 1, (data[0] & 1) != 0);
  const std::vector<uint8_t> payload(data, data + size);
  try {
    const tdvo::DracoMeshCounts counts = tdvo::checkDracoMeshCounts(payload, "fuzz");
    tdvo::checkDracoMemory(counts, payload.size(), tdvo::kDefaultMaxMeshMemoryPerByte, "fuzz");
    tdvo::decodeCheckedDracoMesh(payload, counts, "fuzz");
  } catch (const tdvo::Error&) {
  }
  return 0;
}
