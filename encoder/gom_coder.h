// Geometry coding of one GOM on its own. GOMs share nothing but the grid and the parameters (a
// GOM starts with an I mesh and its P meshes refer only to frames of the same GOM), so they can
// be coded in any order, also in parallel; encodeSequence (sequence_encoder.h) writes the
// results into the stream in GOM order. Everything here is a pure function of its inputs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bitstream/units.h"
#include "common/core/grid.h"
#include "common/core/mesh.h"
#include "encoder/encoder_params.h"
#include "encoder/imesh_encoder.h"

namespace tdvo {

// A coded GOM, ready to be appended to the stream.
struct GomGeometry {
  struct Unit {
    UnitType type;
    std::vector<uint8_t> payload;
  };
  struct Frame {
    std::vector<Vec3i> positions;  // the reconstruction (= the decoder's output)
    size_t iMesh = 0;              // its connectivity and vertex order: iMeshes[iMesh]
    std::vector<Vec3i> input;      // the input quantised to the grid, in input vertex order
  };
  std::vector<Unit> units;             // GOM_HEADER, I_MESH(es), P_MESHes, in stream order
  std::vector<IMeshEncoding> iMeshes;  // one per I mesh of the GOM
  std::vector<Frame> frames;           // the GOM's frames in order
  std::vector<std::string> warnings;   // for stderr, in the order a sequential run meets them
  std::string normals;                 // how the GOM's normals are carried, for the summary
  size_t keyframes = 0;                // frames coded (I or P mesh), not interpolated
};

// What a GOM of P meshes leaves for the next GOM, which may continue its connectivity instead
// of starting a random access point (RandomAccessPeriod).
struct GomContinuation {
  std::shared_ptr<const IMeshEncoding> iMesh;  // the connectivity and vertex order in use
  std::vector<Triangle> inputTriangles;        // the input connectivity it was made from
  size_t inputVertices = 0;
  MeshAttributes inputAttributes;  // the input attributes it was made from (normals: if coded)
  NormalMode normalMode = NormalMode::kNone;  // how its normals are carried (gom_coder.cpp)
  std::vector<Vec3i> last;                    // the GOM's last reconstructed frame (coding order)
};

// Codes frames first .. first + frames.size() - 1 of a sequence as one GOM (`frames` are the
// GOM's input meshes, taken over and released as soon as they are on the grid). `frameName(k)`
// names sequence frame k in error messages. Triangles with a repeated vertex are dropped (a
// warning counts them). Throws Error on input the codec cannot represent (connectivity changing
// inside a GOM of P meshes).
// With `continuation` (from the previous GOM, P-mesh modes only) the GOM continues that GOM's
// connectivity without an I mesh when its first frame's connectivity equals it, else it starts
// a random access point anyway; without, it is a random access point. `next`, when given,
// receives what the following GOM may continue.
GomGeometry encodeGomGeometry(const EncoderParams& params, const Grid& grid, size_t first,
                              std::vector<Mesh> frames,
                              const std::function<std::string(size_t)>& frameName,
                              const GomContinuation* continuation = nullptr,
                              GomContinuation* next = nullptr);

}  // namespace tdvo
