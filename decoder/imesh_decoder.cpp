#include "decoder/imesh_decoder.h"

#include <draco/mesh/mesh.h>

#include "bitstream/syntax.h"
#include "common/core/error.h"
#include "decoder/draco_limits.h"

namespace tdvo {

IntMesh decodeIMesh(const std::vector<uint8_t>& payload, int gridBits, const std::string& context,
                    uint64_t bytesRead, uint64_t memoryPerByte, int quantStep) {
  // Draco allocates from the counts it reads before it checks them against the payload: those
  // counts are checked first (draco_limits.h).
  // Likewise the attribute descriptors, as Draco reaches them (decodeCheckedDracoMesh).
  const DracoMeshCounts counts = checkDracoMeshCounts(payload, context);
  // And what those counts make Draco allocate, against the stream bytes that pay for it.
  checkDracoMemory(counts, bytesRead != 0 ? bytesRead : payload.size(), memoryPerByte, context);
  std::unique_ptr<draco::Mesh> dm = decodeCheckedDracoMesh(payload, counts, context);

  const uint32_t numPoints = dm->num_points();
  const uint32_t numFaces = dm->num_faces();
  if (numPoints == 0 || numPoints > kMaxVertices)
    throw Error(context + ": I mesh has " + std::to_string(numPoints) + " vertices (allowed 1.." +
                std::to_string(kMaxVertices) + ")");
  if (numFaces == 0 || numFaces > kMaxTriangles)
    throw Error(context + ": I mesh has " + std::to_string(numFaces) + " triangles (allowed 1.." +
                std::to_string(kMaxTriangles) + ")");
  const draco::PointAttribute* position = dm->GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (!position || position->data_type() != draco::DT_INT32 || position->num_components() != 3)
    throw Error(context + ": I mesh has no 3-component int32 POSITION attribute");

  IntMesh mesh;
  mesh.positions.resize(numPoints);
  // Draco's values are the grid integers divided by quantStep (im_quant_step).
  const int32_t maxCoordinate = iMeshMaxValue(gridBits, quantStep);
  for (uint32_t i = 0; i < numPoints; ++i) {
    Vec3i& p = mesh.positions[i];
    if (!position->ConvertValue<int32_t>(position->mapped_index(draco::PointIndex(i)), 3, p.data()))
      throw Error(context + ": cannot read position of vertex " + std::to_string(i));
    for (int32_t& c : p) {
      if (c < 0 || c > maxCoordinate)
        throw Error(context + ": vertex " + std::to_string(i) + " coordinate " + std::to_string(c) +
                    " outside the grid [0, " + std::to_string(maxCoordinate) + "]" +
                    (quantStep > 1 ? " (divided by im_quant_step " + std::to_string(quantStep) + ")"
                                   : std::string()));
      c *= quantStep;
    }
  }
  mesh.triangles.resize(numFaces);
  for (uint32_t f = 0; f < numFaces; ++f) {
    const draco::Mesh::Face& face = dm->face(draco::FaceIndex(f));
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = face[k].value();
      if (v >= numPoints)
        throw Error(context + ": triangle " + std::to_string(f) + " refers to vertex " +
                    std::to_string(v) + " of " + std::to_string(numPoints));
      mesh.triangles[f][k] = v;
    }
  }
  return mesh;
}

}  // namespace tdvo
