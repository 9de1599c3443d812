// P-mesh encoding: rate-distortion decisions for the octree clustering and leaf modes, then
// the shared syntax (bitstream/pmesh_syntax.h) writes them.
//
// Decisions. For every octree cell the encoder compares J = D + lambda * R of
//   ZERO            D = sum |m|^2                       (m: motion = target - previous)
//   REPRESENTATIVE  D = sum |m - rep|^2, rep = rounded mean motion of the cell
//   RESIDUAL        D = quantisation error of the residuals, R = their estimated bits
// and of splitting the cell (the children's best J plus the split flag), bottom-up. D is in
// squared grid units, R in estimated bits; rates are estimated from Exp-Golomb code lengths
// with an open-loop prediction (all neighbours' true motions). lambda = 0 keeps the smallest
// distortion and, among equal distortions, the smallest rate: with MotionQuantStep 1 that is
// lossless coding on the grid.
#pragma once

#include <cstdint>
#include <vector>

#include "bitstream/pmesh_syntax.h"

namespace tdvo {

struct PMeshEncoding {
  std::vector<uint8_t> payload;       // pm_cabac_payload
  std::vector<Vec3i> reconstruction;  // the decoder's result for this payload
  uint64_t bins = 0;                  // CABAC bins coded (regular, bypass, terminate)
};

PMeshEncoding encodePMesh(const GomTopology& topology, const std::vector<Vec3i>& previous,
                          const std::vector<Vec3i>& target, const PMeshParams& params,
                          double lambda);

// The AFX-IC-style reference coder: per-vertex temporal DPCM with uniform quantisation
// (residual = round(motion / MotionQuantStep)), no clustering (codeTemporalDpcm).
PMeshEncoding encodeTemporalDpcm(const std::vector<Vec3i>& previous,
                                 const std::vector<Vec3i>& target, const PMeshParams& params);

}  // namespace tdvo
