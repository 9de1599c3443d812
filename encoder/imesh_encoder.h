// I-mesh encoding with Draco, and recovery of the vertex order Draco's decoder produces.
//
// Draco's Edgebreaker coder reorders vertices (and faces). The GOM's vertex order is defined as
// the order the *decoder* produces, so the encoder decodes its own payload (closed loop) and
// works out, for every decoded vertex, which input vertex it came from. Draco's Edgebreaker
// encoder is run directly, so that its record of the input corner each position value was
// coded from gives that mapping exactly, even where vertices coincide (seams, doubled
// surfaces); it is checked against the decoded positions and triangles (each decoded triangle
// must be an input triangle of its own, non-manifold edges included). Should that check ever
// fail, a matcher takes over (and the encoder warns if it leaves decoded triangles without an
// input twin):
//   1. a decoded vertex whose integer position occurs once in the input maps to that vertex;
//   2. the rest are resolved through connectivity: for a decoded triangle (x, y, z) with x and y
//      already mapped to input vertices a and b, z maps to the third vertex of the input triangle
//      that has the directed edge a->b, provided that vertex has z's position (and is the only
//      one: a directed edge of several input triangles, a non-manifold edge, whose third
//      vertices coincide leaves z to step 3);
//   3. anything still open (identical positions in identical surroundings) takes any unused
//      input vertex at the same position: such vertices cannot be told apart by position and
//      connectivity, so any choice is consistent for the I mesh. Step 2 resumes from each such
//      choice, so that a whole component follows it (coincident copies of a surface map copy to
//      copy).
// The mapping is then used to reorder the GOM's later frames, which are P meshes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bitstream/attributes_syntax.h"
#include "bitstream/order_syntax.h"
#include "common/core/mesh.h"

namespace tdvo {

// The most (proper) triangles one vertex of an I mesh may be a corner of: Draco's encoder
// builds its corner table in time quadratic in it (a fan of 80,000 triangles took 6 s, 160,000
// copies of one triangle 17 s), so that encoding stays linear in the mesh, with a constant
// that real meshes (valences of tens) never come near (docs/errors.md, O19).
constexpr uint32_t kMaxVertexTriangles = 4096;

struct IMeshEncoding {
  std::vector<uint8_t> payload;       // im_draco_payload
  int quantStep = 1;                  // im_quant_step
  IntMesh decoded;                    // what every decoder reconstructs
  std::vector<uint32_t> inputIndex;   // decoded vertex -> input vertex
  size_t unmatchedTriangles = 0;      // decoded triangles with no input twin (should be 0)
  MeshOrder order;                    // the output order (inputOrder below)
  std::vector<uint8_t> orderPayload;  // vo_cabac_payload
  bool triangleOrder = true;          // vo_triangle_order
  size_t keptDegenerate = 0;          // input triangles with a repeated vertex, in the output
  size_t droppedDegenerate = 0;       // those that could not be (a vertex Draco dropped)
  DecodedAttributes attributes;       // the ATTRIBUTES unit's (set by the GOM coder)
};

// Encodes `mesh` (grid integers, coordinates < 2^gridBits), losslessly unless `quantStep` > 1.
// `dracoSpeed` is Draco's encoding/decoding speed option (0 = best compression, 10 = fastest). With
// `triangleOrder` the output order keeps the input's triangle list, else the triangles come out in
// coding order (vertices in the input's order either way). Triangles with a repeated vertex, which
// Draco cannot code, are carried in the order (in place; after the others in coding order),
// except one using a vertex no other triangle uses (Draco drops that vertex).
// With `quantStep` > 1 the I mesh is coded coarser than the grid (im_quant_step): each
// coordinate rounded to the nearest multiple of quantStep (at most 2^gridBits - 1), which
// `decoded` holds; the vertex order is still the input's.
IMeshEncoding encodeIMesh(const IntMesh& mesh, int gridBits, int dracoSpeed,
                          bool triangleOrder = true, int quantStep = 1);

// The coordinate `c` (0 <= c < 2^gridBits) rounded to the nearest multiple of `quantStep` that
// is at most 2^gridBits - 1, divided by quantStep: the value Draco codes (im_quant_step).
int32_t iMeshQuantise(int32_t c, int gridBits, int quantStep);

// The matcher (steps 1-3 above), exposed for tests: maps each vertex of `decoded` to a vertex of
// `input`.
std::vector<uint32_t> recoverVertexOrder(const IntMesh& input, const IntMesh& decoded,
                                         size_t* unmatchedTriangles);

// The output order of `decoded` for `input` (docs/bitstream.md, "Output order"): vertices in
// the input's order (vertices Draco dropped leave no gap; the copies Draco made of a
// non-manifold vertex merge back into it); triangles in the input's order and corner rotation,
// each input triangle taking its decoded twin (same output vertices, same orientation); an
// input triangle without one (none unless the matcher above guessed wrong between coincident
// vertices) takes the next decoded triangle no input triangle took; any still left follow.
MeshOrder inputOrder(const IntMesh& input, const IntMesh& decoded,
                     const std::vector<uint32_t>& inputIndex);

}  // namespace tdvo
