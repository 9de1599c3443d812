// A check of the element counts a Draco mesh bitstream declares, made before Draco sees it.
//
// Draco's decoder (1.5.5, Debian 12) allocates from the counts at the start of its
// connectivity data before it finds out that the payload cannot hold that many elements:
// an Edgebreaker payload of 700 bytes declaring 2^30 vertices and 7·10^8 faces made it use
// 16 GB and 113 s before it failed (docs/robustness.md). This check parses the few header
// fields in front of those counts (Draco bitstream specification: header, then
// ParseEdgebreakerConnectivityData / DecodeSequentialConnectivityData) and rejects counts above
// the I-mesh limits of docs/bitstream.md, so Draco's allocation is bounded by what a mesh of
// the largest allowed size needs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace draco {
class Mesh;
}

namespace tdvo {

// The fields of a Draco mesh header that bound Draco's allocations.
struct DracoMeshCounts {
  uint8_t versionMajor = 0, versionMinor = 0;
  uint8_t encoderMethod = 0;     // 0 sequential, 1 Edgebreaker
  uint8_t traversalType = 0;     // Edgebreaker only: 0 standard, 1 predictive, 2 valence
  uint32_t numVertices = 0;      // sequential: num_points; Edgebreaker: num_encoded_vertices
  uint32_t numFaces = 0;         // num_faces
  uint32_t numSplitSymbols = 0;  // Edgebreaker only: num_encoded_split_symbols
};

// The mesh-memory limit (docs/robustness.md, "Memory"): Draco allocates from the vertex and face
// counts of its header (corner tables, attribute values, the mesh's faces) before it finds out
// whether the payload holds that many elements, and the decoder's structures of the GOM follow
// the same counts; but a mesh costs only about a byte per vertex to code. So the counts are
// checked against the stream bytes read so far, B (through the I mesh's unit), before Draco
// sees them: the memory they make the decoder take, estimated as kMeshBytesPerVertex x vertices
// + kMeshBytesPerFace x faces, may be at most kMeshMemoryFree + the limit x B. The estimate is
// an upper bound of what was measured (Draco 1.5.5, a d3dmc GOM of a 490,000-vertex sheet:
// 415 bytes per vertex with its two faces; a header declaring 2^25 faces: 24 bytes per face),
// so the default keeps decoding within 64 MiB + 64 x the stream's size; 0 lifts the limit
// (3dvo-dec --MaxMeshMemoryPerByte). Meshes of up to about 80,000 vertices always pass.
constexpr uint64_t kDefaultMaxMeshMemoryPerByte = 48;
constexpr uint64_t kMeshMemoryFree = uint64_t{40} << 20;  // 40 MiB
constexpr uint64_t kMeshBytesPerVertex = 192;
constexpr uint64_t kMeshBytesPerFace = 160;

// Parses the header and connectivity counts of `payload` and checks them. The payload must be a
// Draco triangle mesh of bitstream version 2.2 (what Draco 1.5 writes) without metadata, coded
// sequentially or with Edgebreaker, declaring at most kMaxVertices vertices and kMaxTriangles
// faces (and, for Edgebreaker, no more symbols than faces and split symbols than symbols, which
// Draco requires too: so its split vertices are bounded as well). Throws Error, prefixed by
// `context`, otherwise. Draco checks everything after these fields itself.
DracoMeshCounts checkDracoMeshCounts(const std::vector<uint8_t>& payload,
                                     const std::string& context);

// The memory-limit check above: throws Error, prefixed by `context`, when `counts` need more than
// kMeshMemoryFree + perByte x bytesRead (perByte 0: no limit).
void checkDracoMemory(const DracoMeshCounts& counts, uint64_t bytesRead, uint64_t perByte,
                      const std::string& context);

// Checks the attribute descriptors at the start of a Draco 2.2 mesh's attribute data (`data`,
// `size`: what follows the connectivity data; Draco specification: DecodeAttributeData,
// ParseAttributeDecodersData), before Draco allocates anything from them: Draco sizes an
// attribute's values as points x components x the type's size, so a payload declaring many
// attributes or components would make it allocate without bound. An I mesh has exactly one
// attribute decoder with exactly one attribute, POSITION, of 3 int32 components (what
// decodeIMesh requires of the decoded mesh anyway). Returns "" when the descriptors pass,
// otherwise what is wrong.
std::string checkDracoAttributeDescriptors(const uint8_t* data, size_t size, bool edgebreaker);

// Decodes a Draco mesh payload whose counts checkDracoMeshCounts has checked, checking its
// attribute descriptors (checkDracoAttributeDescriptors) before Draco reads them. Throws Error
// prefixed by `context` when Draco cannot decode it or the descriptors are refused.
std::unique_ptr<draco::Mesh> decodeCheckedDracoMesh(const std::vector<uint8_t>& payload,
                                                    const DracoMeshCounts& counts,
                                                    const std::string& context);

}  // namespace tdvo
