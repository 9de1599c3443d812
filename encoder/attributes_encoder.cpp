#include "encoder/attributes_encoder.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "bitstream/cabac_io.h"
#include "common/core/error.h"
#include "common/core/warnings.h"

namespace tdvo {

namespace {

// The rotation of `t` that is smallest lexicographically (a triangle's key whatever its
// rotation, repeated vertices included), and how far it is rotated.
std::pair<Triangle, int> smallestRotation(const Triangle& t) {
  Triangle best = t;
  int by = 0;
  for (int r = 1; r < 3; ++r) {
    const Triangle rotated{t[r], t[(r + 1) % 3], t[(r + 2) % 3]};
    if (rotated < best) {
      best = rotated;
      by = r;
    }
  }
  return {best, by};
}

// For each output triangle, its input triangle and the rotation r with output corner c =
// input corner (c + r) % 3.
struct Twin {
  uint32_t triangle;
  int rotation;
};

std::vector<Twin> inputTwins(const IntMesh& input, const IMeshEncoding& i,
                             const std::vector<uint32_t>& inputOf, const std::string& name) {
  std::map<Triangle, std::vector<std::pair<uint32_t, int>>> byKey;  // each list used from its end
  for (uint32_t t = static_cast<uint32_t>(input.triangles.size()); t-- > 0;) {
    const auto [key, by] = smallestRotation(input.triangles[t]);
    byKey[key].push_back({t, by});
  }
  std::vector<Twin> twins;
  twins.reserve(i.order.triangles.size());
  for (size_t t = 0; t < i.order.triangles.size(); ++t) {
    const Triangle& o = i.order.triangles[t];
    const auto [key, by] = smallestRotation({inputOf[o[0]], inputOf[o[1]], inputOf[o[2]]});
    auto it = byKey.find(key);
    if (it == byKey.end() || it->second.empty())
      throw Error(name + ": output triangle " + std::to_string(t) +
                  " has no twin among the input's triangles, so its corners' texture "
                  "coordinates and normals are unknown (coincident vertices Draco's order "
                  "could not tell apart; try DracoSpeed or PMeshMode intra)");
    const auto [input, inputBy] = it->second.back();
    it->second.pop_back();
    // key = output rotated by `by` = input rotated by `inputBy`.
    twins.push_back({input, ((inputBy - by) % 3 + 3) % 3});
  }
  return twins;
}

// Per-corner index triangles of the output from the input's.
std::vector<Triangle> outputIndices(const std::vector<Triangle>& inputIndices,
                                    const std::vector<Twin>& twins) {
  std::vector<Triangle> out;
  out.reserve(twins.size());
  for (const Twin& w : twins) {
    const Triangle& in = inputIndices[w.triangle];
    out.push_back({in[w.rotation], in[(w.rotation + 1) % 3], in[(w.rotation + 2) % 3]});
  }
  return out;
}

// Per-vertex values are coded per output vertex; when the encoder dropped an input vertex (one no
// triangle uses) its value would go with it, so such a frame's values are coded per corner,
// which keeps the input's lists and indices.
bool perVertex(const std::vector<Triangle>& indices, size_t values, const IntMesh& mesh,
               bool everyVertexKept) {
  return everyVertexKept && values == mesh.positions.size() && indices == mesh.triangles;
}

// Values quantised at `bits` must stay below 2^24 steps of 2^-bits.
template <size_t N>
void checkQuantisable(const std::vector<std::array<float, N>>& values, int bits,
                      const std::string& name, const char* what, const char* key) {
  if (bits == 0) return;
  for (size_t i = 0; i < values.size(); ++i)
    for (float f : values[i])
      if (!(std::fabs(std::ldexp(static_cast<double>(f), bits)) < kMaxAttributeQuantValue - 0.5))
        throw Error(name + ": " + what + " " + std::to_string(i) + " has a component (" +
                    std::to_string(f) + ") too large for " + key + " " + std::to_string(bits) +
                    " (magnitudes below 2^" + std::to_string(24 - bits) + ")");
}

}  // namespace

AttributesEncoding encodeAttributes(const IntMesh& input, const IMeshEncoding& i, bool uvs,
                                    NormalMode normals, uint32_t frame, const std::string& name,
                                    int uvQuantBits, int normalQuantBits) {
  const MeshAttributes& in = input.attributes;
  uvs = uvs && in.hasUvs();
  if (normals != NormalMode::kComputed && !in.hasNormals()) normals = NormalMode::kNone;
  // Output vertex -> input vertex (copies Draco made of a vertex are one output vertex).
  std::vector<uint32_t> inputOf(i.order.numVertices);
  for (size_t j = 0; j < i.inputIndex.size(); ++j)
    inputOf[i.order.vertexOutput[j]] = i.inputIndex[j];
  const uint32_t maxValues = static_cast<uint32_t>(3 * i.order.triangles.size());
  std::vector<bool> used(input.positions.size(), false);
  for (uint32_t v : inputOf)
    used[v] = true;
  const bool everyVertexKept = std::find(used.begin(), used.end(), false) == used.end();

  AttributesUnit at;
  at.at_frame = frame;
  at.maxValues = maxValues;
  AttributesEncoding out;
  MeshAttributes& m = out.decoded.values;
  std::vector<Twin> twins;
  auto twinsOnce = [&]() -> const std::vector<Twin>& {
    if (twins.empty()) twins = inputTwins(input, i, inputOf, name);
    return twins;
  };
  // A stream carries at most one value per output corner (at_num_uvs, at_num_normals). When a
  // file has more, some are values no corner refers to: those are left out (with a warning),
  // the others keep their order.
  auto fitCorners = [&](auto& values, std::vector<Triangle>& indices, const char* one,
                        const char* many) {
    if (values.size() <= maxValues) return;
    std::vector<uint32_t> newIndex(values.size(), UINT32_MAX);
    for (const Triangle& t : indices)
      for (const uint32_t k : t)
        newIndex[k] = 0;
    std::remove_reference_t<decltype(values)> kept;
    for (size_t k = 0; k < values.size(); ++k)
      if (newIndex[k] == 0) {
        newIndex[k] = static_cast<uint32_t>(kept.size());
        kept.push_back(values[k]);
      }
    for (Triangle& t : indices)
      for (uint32_t& k : t)
        k = newIndex[k];
    const size_t left = values.size() - kept.size();
    warn(name + ": " + std::to_string(left) + " " + (left == 1 ? one : many) +
         " that no face corner refers to: left out (the stream carries at most one per corner)");
    values = std::move(kept);
  };
  if (uvs && perVertex(in.uvTriangles, in.uvs.size(), input, everyVertexKept)) {
    at.at_uv_mode = static_cast<uint8_t>(UvMode::kPerVertex);
    for (uint32_t v : inputOf)
      m.uvs.push_back(in.uvs[v]);
  } else if (uvs) {
    at.at_uv_mode = static_cast<uint8_t>(UvMode::kPerCorner);
    m.uvs = in.uvs;
    m.uvTriangles = outputIndices(in.uvTriangles, twinsOnce());
    fitCorners(m.uvs, m.uvTriangles, "texture coordinate", "texture coordinates");
    at.at_num_uvs = static_cast<uint32_t>(m.uvs.size());
  }
  if (normals == NormalMode::kComputed) {
    at.at_normal_mode = static_cast<uint8_t>(NormalMode::kComputed);
  } else if (normals != NormalMode::kNone &&
             perVertex(in.normalTriangles, in.normals.size(), input, everyVertexKept)) {
    at.at_normal_mode = static_cast<uint8_t>(NormalMode::kPerVertex);
    for (uint32_t v : inputOf)
      m.normals.push_back(in.normals[v]);
  } else if (normals != NormalMode::kNone) {
    at.at_normal_mode = static_cast<uint8_t>(NormalMode::kPerCorner);
    m.normals = in.normals;
    m.normalTriangles = outputIndices(in.normalTriangles, twinsOnce());
    fitCorners(m.normals, m.normalTriangles, "normal", "normals");
    at.at_num_normals = static_cast<uint32_t>(m.normals.size());
  }
  if (at.at_uv_mode != 0) {
    at.at_uv_origin = static_cast<uint8_t>(in.uvOrigin);
    m.uvOrigin = in.uvOrigin;
    at.at_uv_quant_bits = static_cast<uint8_t>(uvQuantBits);
    checkQuantisable(m.uvs, uvQuantBits, name, "texture coordinate", "UVQuantBits");
  }
  if (!m.normals.empty()) {
    at.at_normal_quant_bits = static_cast<uint8_t>(normalQuantBits);
    checkQuantisable(m.normals, normalQuantBits, name, "normal", "NormalQuantBits");
  }
  CabacWriterIo writer;
  // (Quantised values are replaced by the decoder's.)
  codeAttributes(writer, at, i.order.numVertices, i.order.triangles, out.decoded);
  at.at_cabac_payload = writer.finish();
  out.payload = serialise(at);
  // Closed loop: the decoder's reading is what the encoder meant.
  CabacReaderIo reader(at.at_cabac_payload.data(), at.at_cabac_payload.size(),
                       "encoder's own attributes");
  DecodedAttributes check;
  codeAttributes(reader, at, i.order.numVertices, i.order.triangles, check);
  reader.finish();
  if (check.values != out.decoded.values || check.normalMode != out.decoded.normalMode)
    throw std::logic_error("attributes payload does not decode to the encoder's attributes");
  return out;
}

}  // namespace tdvo
