// Texture coordinates and normals of an I mesh (ATTRIBUTES unit, docs/bitstream.md
// "Attributes"), written once for encoder and decoder.
//
// The unit follows the VERTEX_ORDER unit of each I mesh when sh_attributes_present is 1. Its
// values are in the output order (section 4.1): per-vertex values (mode 1) one per output
// vertex, their index triangles the output triangles; per-corner values (mode 2) a list of
// at_num_* values and, for every output triangle in output order, three indices into it.
// Every frame made from the I mesh (its P meshes, interpolated frames, and GOMs that continue
// it) outputs these attributes; with at_normal_mode 3 the normals are not coded: the decoder
// computes per-vertex normals of each output frame (computeVertexNormals, mesh_attributes.h).
//
// Payload (one CABAC codeword, fresh contexts):
//   if at_uv_mode != 0: if mode 2: indices(at_uv_*); values(2 components, at_uv_delta)
//   if at_normal_mode is 1 or 2: if mode 2: indices(at_normal_*); values(3 components,
//       at_normal_delta)
//   end_of_payload (terminate bin 1)
// values: for each value i in order, for each component c, the signed difference of its key
//   from a prediction: the mean (rounded, halves up) of the component-c keys of the values
//   j < i that share a triangle with i through the index triangles (per vertex: the output
//   triangles), each counted once per triangle corner pair; without any, value i - 1's key
//   (0 for the first). Unquantised (at_*_quant_
//   bits 0), the key of a float32 is its bit pattern b read as an integer that orders like the
//   float: b when the sign bit is clear, -(b & 0x7FFFFFFF) - 1 when set (so every float, -0 and
//   NaNs included, is coded exactly; keys lie in [-2^31, 2^31 - 1], differences within
//   +-(2^32 - 1)). Quantised at b bits, the key is q = round(value * 2^b), |q| < 2^24, and the
//   decoded value q * 2^-b (exact in float).
// indices: for each output triangle, corners 0, 1, 2, with v the corner's output vertex: if
//   an earlier corner of v has an index, at_*_same (regular bin): the index is that corner's
//   (the latest one's); otherwise, or if not the same, when next < count, at_*_new: the index
//   is `next` (1 + the largest index so far, 0 at first); otherwise at_*_index, the index
//   itself (unsigned, <= count - 1).
// The binarisations are those of the vertex order (order_syntax.h: codeSigned, codeUnsigned).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "bitstream/order_syntax.h"
#include "bitstream/syntax.h"
#include "common/core/mesh.h"
#include "common/core/mesh_attributes.h"

namespace tdvo {

struct AttributeContexts {
  OrderContexts::Set uv[2], normal[3], uvIndex, normalIndex;
  ContextModel uvSame, uvNew, normalSame, normalNew;
};

// What the frames made from one I mesh output (beside positions and triangles): the decoded
// attribute values and index triangles (output order), and whether normals are computed.
struct DecodedAttributes {
  MeshAttributes values;
  NormalMode normalMode = NormalMode::kNone;
};

// Sets a frame's attributes (the frame's positions and triangles are the output's).
inline void applyAttributes(const DecodedAttributes& a, IntMesh& frame) {
  frame.attributes = a.values;
  if (a.normalMode != NormalMode::kComputed) return;
  frame.attributes.normals = computeVertexNormals(frame.positions, frame.triangles);
  frame.attributes.normalTriangles = frame.triangles;
}

namespace attributes_detail {

inline int64_t floatKey(float f) {
  uint32_t b;
  std::memcpy(&b, &f, 4);
  return (b & 0x80000000u) ? -int64_t{b & 0x7FFFFFFFu} - 1 : int64_t{b};
}

inline float keyFloat(int64_t key) {
  const uint32_t b =
      key >= 0 ? static_cast<uint32_t>(key) : (0x80000000u | static_cast<uint32_t>(-(key + 1)));
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}

// floor(a / b) for b > 0.
inline int64_t floorDiv(int64_t a, int64_t b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// The quantised value of `f` at `bits` (> 0): round(f * 2^bits), halves away from zero; the
// writer checks that it is within +-kMaxAttributeQuantValue.
inline int64_t quantKey(float f, int bits) {
  return static_cast<int64_t>(std::llround(std::ldexp(static_cast<double>(f), bits)));
}

// `count` values of N components (writing: `values` holds them; with `bits` > 0 they are
// replaced by what the decoder makes of their quantised values).
// The values that share a triangle with each value (through the index triangles), listed once
// per corner pair: start[i] .. start[i + 1] in `list`.
struct ValueNeighbours {
  std::vector<uint32_t> start, list;
  ValueNeighbours(const std::vector<Triangle>& indices, uint32_t count) : start(count + 1, 0) {
    for (const Triangle& t : indices)
      for (uint32_t i : t)
        start[i + 1] += 2;
    for (uint32_t i = 0; i < count; ++i)
      start[i + 1] += start[i];
    list.resize(start[count]);
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (const Triangle& t : indices)
      for (int c = 0; c < 3; ++c) {
        list[fill[t[c]]++] = t[(c + 1) % 3];
        list[fill[t[c]]++] = t[(c + 2) % 3];
      }
  }
};

template <class Io, size_t N>
void codeValues(Io& io, const char* name, OrderContexts::Set* ctx,
                std::vector<std::array<float, N>>& values, uint32_t count, int bits,
                const std::vector<Triangle>& indices) {
  if (Io::kReading) values.assign(count, std::array<float, N>{});
  const ValueNeighbours neighbours(indices, count);
  std::vector<std::array<int64_t, N>> keys(count);
  const int64_t maxKey = bits > 0 ? kMaxAttributeQuantValue : INT32_MAX;
  const int64_t minKey = bits > 0 ? -int64_t{kMaxAttributeQuantValue} : INT32_MIN;
  const uint32_t maxDelta = static_cast<uint32_t>(maxKey - minKey);
  for (uint32_t i = 0; i < count; ++i) {
    std::array<float, N>& value = values[i];
    // The prediction: the mean key of the values already coded that share a triangle with this
    // one, else the previous value's (0 for the first).
    int64_t sum[N] = {};
    int64_t n = 0;
    for (uint32_t k = neighbours.start[i]; k < neighbours.start[i + 1]; ++k) {
      const uint32_t j = neighbours.list[k];
      if (j >= i) continue;
      for (size_t c = 0; c < N; ++c)
        sum[c] += keys[j][c];
      ++n;
    }
    int64_t previous[N] = {};
    for (size_t c = 0; c < N; ++c)
      previous[c] = n > 0 ? floorDiv(2 * sum[c] + n, 2 * n) : i > 0 ? keys[i - 1][c] : 0;
    for (size_t c = 0; c < N; ++c) {
      int64_t delta = 0;
      if (!Io::kReading) {
        const float f = value[c];
        const int64_t key = bits > 0 && std::isfinite(f) && std::fabs(f) < 1e30f ? quantKey(f, bits)
                            : bits > 0                                           ? maxKey + 1
                                                                                 : floatKey(f);
        io.require(key >= minKey && key <= maxKey,
                   std::string(name) + ": a value too large for its quantisation");
        delta = key - previous[c];
      }
      order_detail::codeSigned(io, name, ctx[c], delta, maxDelta);
      const int64_t key = previous[c] + delta;
      if (Io::kReading)
        io.require(key >= minKey && key <= maxKey,
                   std::string(name) + (bits > 0 ? " takes the value past its quantised range"
                                                 : " takes the value past a float's bit pattern"));
      // q * 2^-bits is exact in float (|q| < 2^24).
      value[c] = bits > 0 ? std::ldexp(static_cast<float>(key), -bits) : keyFloat(key);
      keys[i][c] = key;
    }
  }
}

// The index triangles of `count` values, one per output triangle (writing: `indices` holds
// them).
template <class Io>
void codeIndices(Io& io, const char* sameName, const char* newName, const char* indexName,
                 ContextModel& same, ContextModel& fresh, OrderContexts::Set& ctx,
                 const std::vector<Triangle>& triangles, uint32_t numVertices,
                 std::vector<Triangle>& indices, uint32_t count) {
  constexpr uint32_t kNone = UINT32_MAX;
  if (Io::kReading) indices.assign(triangles.size(), Triangle{0, 0, 0});
  std::vector<uint32_t> last(numVertices, kNone);
  uint32_t next = 0;
  for (size_t t = 0; t < triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const uint32_t v = triangles[t][c];
      uint32_t index = Io::kReading ? 0 : indices[t][c];
      if (!Io::kReading) io.require(index < count, std::string(indexName) + " out of range");
      unsigned isSame = 0, isNew = 0;
      if (last[v] != kNone) {
        isSame = index == last[v];
        io.bin(sameName, same, isSame);
      }
      if (isSame) {
        index = last[v];
      } else {
        if (next < count) {
          isNew = index == next;
          io.bin(newName, fresh, isNew);
        }
        if (isNew)
          index = next;
        else
          order_detail::codeUnsigned(io, indexName, ctx, index, count - 1);
      }
      indices[t][c] = index;
      last[v] = index;
      if (index >= next) next = index + 1;
    }
}

}  // namespace attributes_detail

// The payload of an ATTRIBUTES unit whose header is `at`, for an I mesh whose output has
// `numVertices` vertices and `triangles` (output order). Writing: `a` holds what the modes say
// (per-vertex values: one per output vertex, index triangles = `triangles`). Reading: fills
// `a`.
template <class Io>
void codeAttributes(Io& io, const AttributesUnit& at, uint32_t numVertices,
                    const std::vector<Triangle>& triangles, DecodedAttributes& a) {
  using namespace attributes_detail;
  AttributeContexts ctx;
  MeshAttributes& m = a.values;
  const auto uvMode = static_cast<UvMode>(at.at_uv_mode);
  const auto normalMode = static_cast<NormalMode>(at.at_normal_mode);
  a.normalMode = normalMode;
  if (uvMode != UvMode::kNone) {
    const bool perCorner = uvMode == UvMode::kPerCorner;
    const uint32_t count = perCorner ? at.at_num_uvs : numVertices;
    if (!Io::kReading) io.require(m.uvs.size() == count, "at_uv values: wrong count");
    if (!Io::kReading)
      io.require(m.uvOrigin == static_cast<UvOrigin>(at.at_uv_origin),
                 "at_uv_origin: not the values'");
    m.uvOrigin = static_cast<UvOrigin>(at.at_uv_origin);
    if (perCorner)
      codeIndices(io, "at_uv_same", "at_uv_new", "at_uv_index", ctx.uvSame, ctx.uvNew, ctx.uvIndex,
                  triangles, numVertices, m.uvTriangles, count);
    else
      m.uvTriangles = triangles;
    codeValues(io, "at_uv_delta", ctx.uv, m.uvs, count, at.at_uv_quant_bits, m.uvTriangles);
  } else if (Io::kReading) {
    m.uvs.clear();
    m.uvTriangles.clear();
  }
  if (normalMode == NormalMode::kPerVertex || normalMode == NormalMode::kPerCorner) {
    const bool perCorner = normalMode == NormalMode::kPerCorner;
    const uint32_t count = perCorner ? at.at_num_normals : numVertices;
    if (!Io::kReading) io.require(m.normals.size() == count, "at_normal values: wrong count");
    if (perCorner)
      codeIndices(io, "at_normal_same", "at_normal_new", "at_normal_index", ctx.normalSame,
                  ctx.normalNew, ctx.normalIndex, triangles, numVertices, m.normalTriangles, count);
    else
      m.normalTriangles = triangles;
    codeValues(io, "at_normal_delta", ctx.normal, m.normals, count, at.at_normal_quant_bits,
               m.normalTriangles);
  } else if (Io::kReading) {
    m.normals.clear();
    m.normalTriangles.clear();
  }
}

}  // namespace tdvo
