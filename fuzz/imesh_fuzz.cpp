// Fuzz target: the I-mesh decoder (decodeIMesh: Draco, then the checks on its output) and the
// GOM topology built from the decoded mesh (GomTopology::build, as for a d3dmc GOM), which
// sees whatever connectivity a Draco payload can describe.
//
// The input is an im_draco_payload, decoded on a 20-bit grid (the widest: the most payloads get
// past the coordinate check). Seeds: the I-mesh payloads of the conformance streams.
#include <cstdint>
#include <vector>

#include "common/core/error.h"
#include "common/geometry/pmesh_prediction.h"
#include "decoder/imesh_decoder.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> payload(data, data + size);
  try {
    const tdvo::IntMesh mesh = tdvo::decodeIMesh(payload, 20, "fuzz I mesh");
    tdvo::GomTopology::build(mesh);
  } catch (const tdvo::Error&) {
  }
  return 0;
}
