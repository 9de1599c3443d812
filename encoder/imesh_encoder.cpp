#include "encoder/imesh_encoder.h"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/compression/mesh/mesh_edgebreaker_encoder.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "bitstream/syntax.h"
#include "common/core/error.h"
#include "decoder/imesh_decoder.h"

namespace tdvo {

namespace {

uint64_t positionKey(const Vec3i& p) {
  // Coordinates are below 2^20, so three of them pack into 60 bits.
  return uint64_t(uint32_t(p[0])) << 40 | uint64_t(uint32_t(p[1])) << 20 | uint64_t(uint32_t(p[2]));
}

uint64_t edgeKey(uint32_t a, uint32_t b) {
  return uint64_t(a) << 32 | b;
}

constexpr uint32_t kUnmapped = UINT32_MAX;

// Directed edge a->b of a triangle of `mesh` -> its third vertices, one per such triangle in
// the mesh's order (several where a non-manifold edge is used twice in the same direction).
using ThirdVertices = std::unordered_map<uint64_t, std::vector<uint32_t>>;
ThirdVertices thirdVertices(const IntMesh& mesh) {
  ThirdVertices third;
  third.reserve(mesh.triangles.size() * 3);
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      third[edgeKey(t[k], t[(k + 1) % 3])].push_back(t[(k + 2) % 3]);
  return third;
}

// `t` rotated to start at its smallest index (orientation kept).
Triangle canonical(Triangle t) {
  while (t[0] > t[1] || t[0] > t[2])
    t = Triangle{t[1], t[2], t[0]};
  return t;
}

// Decoded triangles that `map` (decoded vertex -> input vertex) does not take to an input
// triangle of their own: each input triangle (same vertices, same orientation, any rotation) is
// the twin of at most one decoded triangle, so that two decoded triangles cannot both pass as
// one input triangle (which would hide a merged vertex).
size_t countUnmatched(const IntMesh& input, const IntMesh& decoded,
                      const std::vector<uint32_t>& map) {
  std::vector<Triangle> in(input.triangles.size()), out(decoded.triangles.size());
  for (size_t i = 0; i < in.size(); ++i)
    in[i] = canonical(input.triangles[i]);
  for (size_t i = 0; i < out.size(); ++i) {
    const Triangle& t = decoded.triangles[i];
    out[i] = canonical({map[t[0]], map[t[1]], map[t[2]]});
  }
  std::sort(in.begin(), in.end());
  std::sort(out.begin(), out.end());
  // Decoded triangles minus the input's (as multisets).
  size_t matched = 0;
  for (size_t a = 0, b = 0; a < in.size() && b < out.size();) {
    if (in[a] < out[b]) {
      ++a;
    } else if (out[b] < in[a]) {
      ++b;
    } else {
      ++matched, ++a, ++b;
    }
  }
  return out.size() - matched;
}

// The Draco mesh of `mesh`, each point its own position value.
void fillDracoMesh(const IntMesh& mesh, int quantStep, draco::Mesh& dm) {
  const uint32_t n = static_cast<uint32_t>(mesh.positions.size());
  dm.set_num_points(n);
  for (const Triangle& t : mesh.triangles)
    dm.AddFace({draco::PointIndex(t[0]), draco::PointIndex(t[1]), draco::PointIndex(t[2])});
  draco::GeometryAttribute attribute;
  attribute.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_INT32, false,
                 sizeof(int32_t) * 3, 0);
  const int id = dm.AddAttribute(attribute, true, n);
  for (uint32_t i = 0; i < n; ++i) {
    Vec3i q = mesh.positions[i];
    for (int32_t& c : q)
      c /= quantStep;  // exact: the positions are multiples of it
    dm.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(i), q.data());
  }
}

// Draco's Edgebreaker encoder, run directly (draco::Encoder does the same with these options
// but keeps what follows to itself): the payload, and for each position value in coding order
// the corner of `dm` it was coded from.
std::vector<uint8_t> encodeDraco(const draco::Mesh& dm, int dracoSpeed,
                                 std::vector<draco::CornerIndex>& valueCorner) {
  draco::EncoderOptions options = draco::EncoderOptions::CreateDefaultOptions();
  options.SetSpeed(dracoSpeed, dracoSpeed);
  options.SetGlobalInt("encoding_method", draco::MESH_EDGEBREAKER_ENCODING);
  draco::MeshEdgebreakerEncoder encoder;
  encoder.SetMesh(dm);
  draco::EncoderBuffer buffer;
  const draco::Status status = encoder.Encode(options, &buffer);
  if (!status.ok()) throw Error("Draco cannot encode the I mesh: " + status.error_msg_string());
  const draco::MeshAttributeIndicesEncodingData* data =
      encoder.GetAttributeEncodingData(dm.GetNamedAttributeId(draco::GeometryAttribute::POSITION));
  valueCorner =
      data ? data->encoded_attribute_value_index_to_corner_map : std::vector<draco::CornerIndex>{};
  return std::vector<uint8_t>(buffer.data(), buffer.data() + buffer.size());
}

// The exact vertex mapping: decoded vertex j has the position value mapped_index(j) (in coding
// order), coded from a corner of the input mesh, and so from that corner's input vertex (the
// copies Draco makes of a non-manifold vertex map back to it). Checked (positions, and every
// decoded triangle an input triangle); empty if anything disagrees, and the matcher
// (recoverVertexOrder) then works the mapping out.
std::vector<uint32_t> exactVertexOrder(const std::vector<uint8_t>& payload,
                                       const std::vector<draco::CornerIndex>& valueCorner,
                                       const IntMesh& mesh, const IntMesh& decoded) {
  draco::DecoderBuffer in;
  in.Init(reinterpret_cast<const char*>(payload.data()), payload.size());
  draco::Decoder decoder;
  auto result = decoder.DecodeMeshFromBuffer(&in);
  if (!result.ok() || result.value()->num_points() != decoded.positions.size()) return {};
  const draco::PointAttribute* position =
      result.value()->GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (!position) return {};
  std::vector<uint32_t> index(decoded.positions.size());
  for (uint32_t j = 0; j < index.size(); ++j) {
    const uint32_t value = position->mapped_index(draco::PointIndex(j)).value();
    if (value >= valueCorner.size() || valueCorner[value].value() / 3 >= mesh.triangles.size())
      return {};
    const uint32_t corner = valueCorner[value].value();
    index[j] = mesh.triangles[corner / 3][corner % 3];
    if (mesh.positions[index[j]] != decoded.positions[j]) return {};
  }
  if (countUnmatched(mesh, decoded, index) != 0) return {};
  return index;
}

}  // namespace

std::vector<uint32_t> recoverVertexOrder(const IntMesh& input, const IntMesh& decoded,
                                         size_t* unmatchedTriangles) {
  std::unordered_map<uint64_t, std::vector<uint32_t>> byPosition;
  byPosition.reserve(input.positions.size());
  for (uint32_t i = 0; i < input.positions.size(); ++i)
    byPosition[positionKey(input.positions[i])].push_back(i);

  std::vector<uint32_t> map(decoded.positions.size(), kUnmapped);
  for (uint32_t j = 0; j < decoded.positions.size(); ++j) {
    auto it = byPosition.find(positionKey(decoded.positions[j]));
    if (it == byPosition.end())
      throw std::logic_error("Draco round trip produced a position the input does not have");
    if (it->second.size() == 1) map[j] = it->second[0];
  }

  // Directed edge a->b of an input triangle -> its third vertex.
  const ThirdVertices thirdVertex = thirdVertices(input);

  std::vector<bool> used(input.positions.size(), false);
  for (uint32_t m : map)
    if (m != kUnmapped) used[m] = true;

  // Step 2, as a flood fill: every newly mapped vertex is queued and its triangles are tried.
  std::vector<std::vector<uint32_t>> incident(decoded.positions.size());
  for (uint32_t t = 0; t < decoded.triangles.size(); ++t)
    for (uint32_t v : decoded.triangles[t])
      incident[v].push_back(t);
  std::vector<uint32_t> queue;
  for (uint32_t j = 0; j < map.size(); ++j)
    if (map[j] != kUnmapped) queue.push_back(j);
  // Step 2 as a flood fill from the queued vertices: a triangle with two mapped corners whose
  // input edge has its third vertex at the decoded position maps it. `mapped`, when given,
  // receives the vertices mapped.
  auto propagate = [&](std::vector<uint32_t>* mapped) {
    while (!queue.empty()) {
      const uint32_t v = queue.back();
      queue.pop_back();
      for (uint32_t ti : incident[v]) {
        const Triangle& t = decoded.triangles[ti];
        for (int k = 0; k < 3; ++k) {
          const uint32_t x = t[k], y = t[(k + 1) % 3], z = t[(k + 2) % 3];
          if (map[z] != kUnmapped || map[x] == kUnmapped || map[y] == kUnmapped) continue;
          auto it = thirdVertex.find(edgeKey(map[x], map[y]));
          if (it == thirdVertex.end()) continue;
          // The third vertex at z's position; none if there are several such (a non-manifold
          // edge whose triangles have coincident third vertices): step 3 then decides.
          uint32_t third = kUnmapped;
          bool ambiguous = false;
          for (uint32_t c : it->second)
            if (input.positions[c] == decoded.positions[z] && c != third) {
              ambiguous = ambiguous || third != kUnmapped;
              third = c;
            }
          if (third == kUnmapped || ambiguous) continue;
          map[z] = third;
          used[map[z]] = true;
          queue.push_back(z);
          if (mapped) mapped->push_back(z);
        }
      }
    }
  };
  propagate(nullptr);

  // Step 3: a leftover takes an input vertex at the same position, and step 2 then continues
  // from it. Leftovers next to mapped vertices come first, each taking the candidate whose input
  // edges agree with most of its mapped neighbours (on a seam, the copy on the right side);
  // only when none is left does the next leftover in order take any candidate, unused ones
  // first. Resuming the flood fill after every choice keeps a component consistent: two
  // coincident copies of a surface map copy to copy instead of mixing vertices of both (which
  // would tear the GOM's P meshes apart when they separate).
  auto score = [&](uint32_t j, uint32_t c) {
    int agree = 0;
    for (uint32_t ti : incident[j])
      for (uint32_t x : decoded.triangles[ti])
        if (x != j && map[x] != kUnmapped)
          agree +=
              int(thirdVertex.count(edgeKey(map[x], c)) + thirdVertex.count(edgeKey(c, map[x])));
    return agree;
  };
  std::vector<uint32_t> frontier;
  auto settle = [&](uint32_t j, uint32_t c) {
    map[j] = c;
    used[c] = true;
    queue.push_back(j);
    // The flood fill, noting the vertices it maps so that their open neighbours are tried next.
    std::vector<uint32_t> mapped{j};
    propagate(&mapped);
    for (uint32_t v : mapped)
      for (uint32_t ti : incident[v])
        for (uint32_t x : decoded.triangles[ti])
          if (map[x] == kUnmapped) frontier.push_back(x);
  };
  auto best = [&](uint32_t j, int& bestScore) {
    const std::vector<uint32_t>& candidates = byPosition[positionKey(decoded.positions[j])];
    bool anyUnused = false;
    for (uint32_t c : candidates)
      anyUnused = anyUnused || !used[c];
    uint32_t choice = candidates[0];
    bestScore = -1;
    for (uint32_t c : candidates) {
      if (anyUnused && used[c]) continue;
      const int sc = score(j, c);
      if (sc > bestScore) {
        bestScore = sc;
        choice = c;
      }
    }
    return choice;
  };
  for (uint32_t j = 0; j < map.size(); ++j)
    if (map[j] != kUnmapped)
      for (uint32_t ti : incident[j])
        for (uint32_t x : decoded.triangles[ti])
          if (map[x] == kUnmapped) frontier.push_back(x);
  for (uint32_t next = 0;;) {
    while (!frontier.empty()) {
      const uint32_t j = frontier.back();
      frontier.pop_back();
      if (map[j] != kUnmapped) continue;
      int bestScore = 0;
      const uint32_t c = best(j, bestScore);
      if (bestScore > 0) settle(j, c);
    }
    while (next < map.size() && map[next] != kUnmapped)
      ++next;
    if (next == map.size()) break;
    int bestScore = 0;
    settle(next, best(next, bestScore));
  }

  if (unmatchedTriangles) *unmatchedTriangles = countUnmatched(input, decoded, map);
  return map;
}

MeshOrder inputOrder(const IntMesh& input, const IntMesh& decoded,
                     const std::vector<uint32_t>& inputIndex) {
  const uint32_t n = static_cast<uint32_t>(decoded.positions.size());
  std::vector<uint32_t> byInput(n);
  for (uint32_t j = 0; j < n; ++j)
    byInput[j] = j;
  std::stable_sort(byInput.begin(), byInput.end(),
                   [&](uint32_t a, uint32_t b) { return inputIndex[a] < inputIndex[b]; });
  // Output index of each input vertex Draco kept (copies Draco made of one merge again).
  MeshOrder order;
  order.vertexOutput.resize(n);
  std::vector<uint32_t> firstOutput(input.positions.size(), kUnmapped);
  for (uint32_t o = 0; o < n; ++o) {
    uint32_t& f = firstOutput[inputIndex[byInput[o]]];
    if (f == kUnmapped) f = order.numVertices++;
    order.vertexOutput[byInput[o]] = f;
  }
  // Decoded triangles by their output vertices, rotated to start at the smallest index (the
  // orientation is kept); each list is used from its front.
  struct TriangleHash {
    size_t operator()(const Triangle& t) const {
      return std::hash<uint64_t>()((uint64_t(t[0]) * 0x9E3779B97F4A7C15ull) ^
                                   (uint64_t(t[1]) << 32 | t[2]));
    }
  };
  std::unordered_map<Triangle, std::vector<uint32_t>, TriangleHash> twins;
  for (uint32_t t = decoded.triangles.size(); t-- > 0;) {
    const Triangle& d = decoded.triangles[t];
    twins[canonical({order.vertexOutput[d[0]], order.vertexOutput[d[1]], order.vertexOutput[d[2]]})]
        .push_back(t);
  }
  // Each input triangle takes its twin; those without one take, in order, the decoded
  // triangles no input triangle took (so that one mismatch does not shift the rest); decoded
  // triangles still left follow.
  constexpr uint32_t kNone = UINT32_MAX;
  std::vector<uint32_t> twin(input.triangles.size(), kNone);
  std::vector<bool> taken(decoded.triangles.size(), false);
  for (size_t i = 0; i < input.triangles.size(); ++i) {
    const Triangle& t = input.triangles[i];
    if (firstOutput[t[0]] == kUnmapped || firstOutput[t[1]] == kUnmapped ||
        firstOutput[t[2]] == kUnmapped)
      continue;
    auto it = twins.find(canonical({firstOutput[t[0]], firstOutput[t[1]], firstOutput[t[2]]}));
    if (it == twins.end() || it->second.empty()) continue;
    twin[i] = it->second.back();
    taken[twin[i]] = true;
    it->second.pop_back();
  }
  auto asOutput = [&](uint32_t t) {
    const Triangle& d = decoded.triangles[t];
    return Triangle{order.vertexOutput[d[0]], order.vertexOutput[d[1]], order.vertexOutput[d[2]]};
  };
  uint32_t leftover = 0;
  auto nextLeftover = [&]() {
    while (leftover < decoded.triangles.size() && taken[leftover])
      ++leftover;
    return leftover < decoded.triangles.size() ? leftover++ : kNone;
  };
  for (size_t i = 0; i < input.triangles.size(); ++i) {
    const Triangle& t = input.triangles[i];
    if (twin[i] != kNone) {
      order.triangles.push_back({firstOutput[t[0]], firstOutput[t[1]], firstOutput[t[2]]});
    } else {
      const uint32_t d = nextLeftover();
      if (d != kNone) order.triangles.push_back(asOutput(d));
    }
  }
  for (uint32_t d = nextLeftover(); d != kNone; d = nextLeftover())
    order.triangles.push_back(asOutput(d));
  return order;
}

int32_t iMeshQuantise(int32_t c, int gridBits, int quantStep) {
  return std::min((c + quantStep / 2) / quantStep, iMeshMaxValue(gridBits, quantStep));
}

IMeshEncoding encodeIMesh(const IntMesh& input, int gridBits, int dracoSpeed, bool triangleOrder,
                          int quantStep) {
  // Draco cannot code triangles with a repeated vertex: they go to the VERTEX_ORDER unit, each
  // with the number of proper triangles before it in the input's list.
  IntMesh mesh;
  mesh.positions = input.positions;
  // The I mesh the decoder makes (im_quant_step): the matching below compares with it.
  if (quantStep > 1)
    for (Vec3i& p : mesh.positions)
      for (int32_t& c : p)
        c = iMeshQuantise(c, gridBits, quantStep) * quantStep;
  std::vector<Triangle> degenerate;
  std::vector<uint32_t> properBefore;
  for (const Triangle& t : input.triangles)
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      degenerate.push_back(t);
      properBefore.push_back(static_cast<uint32_t>(mesh.triangles.size()));
    } else {
      mesh.triangles.push_back(t);
    }
  IMeshEncoding out;
  draco::Mesh dm;
  fillDracoMesh(mesh, quantStep, dm);
  std::vector<draco::CornerIndex> valueCorner;
  out.payload = encodeDraco(dm, dracoSpeed, valueCorner);
  out.quantStep = quantStep;
  // No mesh-memory limit: the encoder holds the mesh anyway.
  out.decoded = decodeIMesh(out.payload, gridBits, "encoder's own I mesh", 0, 0, quantStep);
  out.inputIndex = exactVertexOrder(out.payload, valueCorner, mesh, out.decoded);
  if (out.inputIndex.empty())
    out.inputIndex = recoverVertexOrder(mesh, out.decoded, &out.unmatchedTriangles);
  out.order = inputOrder(mesh, out.decoded, out.inputIndex);
  out.triangleOrder = triangleOrder;
  if (!triangleOrder)
    for (size_t t = 0; t < out.decoded.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k)
        out.order.triangles[t][k] = out.order.vertexOutput[out.decoded.triangles[t][k]];
  // The degenerate triangles, in output vertex indices, in place (after the others in coding
  // order). One whose vertex Draco did not keep (no proper triangle uses it) cannot be output,
  // nor more of them than proper triangles (the bound of vo_num_degenerate).
  {
    std::vector<uint32_t> outputOf(mesh.positions.size(), kUnmapped);
    for (size_t j = 0; j < out.decoded.positions.size(); ++j)
      outputOf[out.inputIndex[j]] = out.order.vertexOutput[j];
    const uint32_t numTriangles = static_cast<uint32_t>(out.order.triangles.size());
    std::vector<Triangle> merged;
    uint32_t next = 0;  // proper triangles merged so far
    for (size_t d = 0; d < degenerate.size(); ++d) {
      const Triangle& t = degenerate[d];
      if (outputOf[t[0]] == kUnmapped || outputOf[t[1]] == kUnmapped ||
          outputOf[t[2]] == kUnmapped || out.order.degenerate.size() >= numTriangles) {
        ++out.droppedDegenerate;
        continue;
      }
      const uint32_t before =
          triangleOrder ? std::min(properBefore[d], numTriangles) : numTriangles;
      for (; next < before; ++next)
        merged.push_back(out.order.triangles[next]);
      out.order.degenerate.push_back(static_cast<uint32_t>(merged.size()));
      merged.push_back({outputOf[t[0]], outputOf[t[1]], outputOf[t[2]]});
    }
    for (; next < numTriangles; ++next)
      merged.push_back(out.order.triangles[next]);
    out.order.triangles = std::move(merged);
    out.keptDegenerate = out.order.degenerate.size();
  }
  CabacWriterIo writer;
  codeMeshOrder(writer, out.decoded, out.order, triangleOrder);
  out.orderPayload = writer.finish();
  // Closed loop: the decoder's reading of the payload is the order the encoder meant.
  CabacReaderIo reader(out.orderPayload.data(), out.orderPayload.size(), "encoder's own order");
  MeshOrder check;
  check.numVertices = out.order.numVertices;
  codeMeshOrder(reader, out.decoded, check, triangleOrder);
  reader.finish();
  if (check.vertexOutput != out.order.vertexOutput || check.triangles != out.order.triangles ||
      check.degenerate != out.order.degenerate)
    throw std::logic_error("vertex order payload does not decode to the encoder's order");
  return out;
}

}  // namespace tdvo
