// Fuzz target: the P-mesh decoders (decodePMesh for d3dmc, decodeTemporalDpcm for afxic).
//
// The GOM is fixed: the I mesh of conformance stream d3dmc_lossless_g8 (162 vertices, 12-bit
// grid), made again at start-up from its committed input (conformance/inputs/blob, 12 frames,
// GridBits 12, DracoSpeed 0) by the I-mesh encoder, so that it does not depend on the syntax
// version of the committed streams. It gives the topology and the previous frame. The input is
// a 4-byte header followed by a pm_cabac_payload:
//   byte 0     bit 0: 0 d3dmc, 1 afxic
//   bytes 1-2  gh_motion_quant_step - 1 (u16 LE, taken modulo 4096)
//   byte 3     gh_max_octree_depth (taken modulo sh_grid_bits + 1)
// Seeds: the P-mesh payloads of the conformance streams with their GOM's header values
// (fuzz/make_corpus.cpp); the one of d3dmc_lossless_g8's frame 1 decodes exactly.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "bitstream/pmesh_syntax.h"
#include "common/core/error.h"
#include "common/core/obj_io.h"
#include "common/core/sequence.h"
#include "decoder/pmesh_decoder.h"
#include "encoder/imesh_encoder.h"
#include "encoder/sequence_encoder.h"
#include "fuzz/fuzz_support.h"

namespace {

struct FixedGom {
  tdvo::IntMesh iMesh;
  tdvo::GomTopology topology;
  int gridBits = 12;
};

const FixedGom& fixedGom() {
  static const FixedGom gom = [] {
    FixedGom g;
    const std::string pattern =
        std::string(TDVO_SOURCE_DIR) + "/conformance/inputs/blob/%04d.obj.gz";
    try {
      std::vector<tdvo::Mesh> frames;
      for (int f = 0; f < 12; ++f)
        frames.push_back(tdvo::readObj(tdvo::framePath(pattern, f)));
      const tdvo::Grid grid = tdvo::gridForSequence(frames, g.gridBits);
      g.iMesh = tdvo::encodeIMesh(grid.quantise(frames[0]), g.gridBits, 0).decoded;
    } catch (const tdvo::Error& e) {
      std::fprintf(stderr, "pmesh fuzz target: cannot make its fixed GOM: %s\n", e.what());
      std::abort();
    }
    g.topology = tdvo::GomTopology::build(g.iMesh);
    return g;
  }();
  return gom;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const FixedGom& gom = fixedGom();
  if (size < 4) return 0;
  tdvo::PMeshParams params;
  params.gridBits = gom.gridBits;
  params.quantStep = 1 + (data[1] | data[2] << 8) % 4096;
  params.maxDepth = data[3] % (gom.gridBits + 1);
  const std::vector<uint8_t> payload(data + 4, data + size);
  try {
    if (data[0] & 1)
      tdvo::decodeTemporalDpcm(payload, gom.iMesh.positions, params, "fuzz P mesh");
    else
      tdvo::decodePMesh(payload, gom.topology, gom.iMesh.positions, params, "fuzz P mesh");
  } catch (const tdvo::Error&) {
  }
  return 0;
}
