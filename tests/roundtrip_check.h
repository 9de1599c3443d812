// The checks of an encode → decode round trip at library level, shared by roundtrip_test and
// horse_test: the encoder's reconstruction equals the decoder's output (MD5 lines and meshes),
// the decoder's grid is the encoder's, every input vertex is decoded once and lies within half
// a grid step of its decoded vertex, and the decoded frames are in the input's vertex order with
// the input's triangle list. Uses GoogleTest assertions.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/core/md5.h"
#include "decoder/stream_decoder.h"
#include "encoder/sequence_encoder.h"

namespace tdvo {
namespace test {

struct RoundTrip {
  Grid grid;
  EncodedSequence coded;
  std::vector<IntMesh> encoderFrames, decoderFrames;
  std::vector<std::string> encoderLines, decoderLines;
  SequenceHeader decodedHeader;
  Grid decodedGrid;
};

inline RoundTrip encodeAndDecode(const std::vector<Mesh>& frames, const EncoderParams& params) {
  RoundTrip r;
  r.grid = gridForSequence(frames, params.gridBits);
  r.coded = encodeSequence(params, r.grid, frames, {}, [&](int frame, const IntMesh& mesh) {
    EXPECT_EQ(frame, static_cast<int>(r.encoderFrames.size()));
    r.encoderFrames.push_back(mesh);
    r.encoderLines.push_back(geometryHashLine(frame, mesh));
  });
  StreamDecoder decoder(r.coded.stream.data(), r.coded.stream.size(), "rt.3dvo");
  decoder.decode([&](int frame, const IntMesh& mesh) {
    EXPECT_EQ(frame, static_cast<int>(r.decoderFrames.size()));
    r.decoderFrames.push_back(mesh);
    r.decoderLines.push_back(geometryHashLine(frame, mesh));
  });
  r.decodedHeader = decoder.sequenceHeader();
  r.decodedGrid = decoder.grid();
  return r;
}

// A triangle rotated so that its smallest index comes first (orientation kept).
inline Triangle canonical(const Triangle& t) {
  const int k = static_cast<int>(std::min_element(t.begin(), t.end()) - t.begin());
  return {t[k], t[(k + 1) % 3], t[(k + 2) % 3]};
}

inline std::vector<Triangle> canonicalSorted(std::vector<Triangle> triangles) {
  for (Triangle& t : triangles)
    t = canonical(t);
  std::sort(triangles.begin(), triangles.end());
  return triangles;
}

// The decoded connectivity expressed in input vertex numbers, canonical and sorted.
inline std::vector<Triangle> decodedAsInput(const IntMesh& decoded,
                                            const std::vector<uint32_t>& index) {
  std::vector<Triangle> out;
  for (const Triangle& t : decoded.triangles)
    out.push_back({index.at(t[0]), index.at(t[1]), index.at(t[2])});
  return canonicalSorted(out);
}

// Everything a correct round trip guarantees.
inline void checkRoundTrip(const std::vector<Mesh>& frames, const RoundTrip& r) {
  ASSERT_EQ(r.encoderFrames.size(), frames.size());
  ASSERT_EQ(r.decoderFrames.size(), frames.size());
  ASSERT_EQ(r.coded.frameInputIndex.size(), frames.size());
  EXPECT_EQ(r.encoderLines, r.decoderLines);

  // The decoder's grid is the encoder's, exactly.
  EXPECT_EQ(r.decodedHeader.sh_frame_count, frames.size());
  EXPECT_EQ(r.decodedGrid.bits, r.grid.bits);
  EXPECT_EQ(r.decodedGrid.step, r.grid.step);
  EXPECT_EQ(r.decodedGrid.origin, r.grid.origin);

  uint64_t vertexFrames = 0;
  for (size_t f = 0; f < frames.size(); ++f) {
    const IntMesh& dec = r.decoderFrames[f];
    const std::vector<uint32_t>& index = r.coded.frameInputIndex[f];
    EXPECT_EQ(dec.positions, r.encoderFrames[f].positions) << "frame " << f;
    EXPECT_EQ(dec.triangles, r.encoderFrames[f].triangles) << "frame " << f;
    ASSERT_EQ(dec.positions.size(), index.size()) << "frame " << f;
    vertexFrames += dec.positions.size();

    // Every input vertex is decoded exactly once.
    std::vector<uint32_t> sorted = index;
    std::sort(sorted.begin(), sorted.end());
    std::vector<uint32_t> all(frames[f].positions.size());
    for (uint32_t i = 0; i < all.size(); ++i)
      all[i] = i;
    EXPECT_EQ(sorted, all) << "frame " << f << ": decoded vertices are not a permutation";

    // Within half a grid step per axis, plus the rounding of dequantisation.
    const double bound = r.grid.step / 2 * (1 + 1e-9) + 1e-12;
    double worst = 0;
    for (size_t j = 0; j < index.size(); ++j) {
      ASSERT_LT(index[j], frames[f].positions.size());
      const Vec3d p = r.decodedGrid.dequantise(dec.positions[j]);
      const Vec3d& in = frames[f].positions[index[j]];
      for (int a = 0; a < 3; ++a) {
        worst = std::max(worst, std::fabs(p[a] - in[a]));
        ASSERT_LE(std::fabs(p[a] - in[a]), bound)
            << "frame " << f << " decoded vertex " << j << " (input " << index[j] << ") axis " << a;
      }
    }
    EXPECT_GT(worst, 0.0);  // the check above is not vacuous: the grid does move vertices

    EXPECT_EQ(decodedAsInput(dec, index), canonicalSorted(frames[f].triangles))
        << "frame " << f << ": decoded connectivity differs from the input's";

    // Output in the input's order: the vertices (the identity when Draco kept every vertex as
    // it is, else still ascending) and the triangles, exactly.
    EXPECT_TRUE(std::is_sorted(index.begin(), index.end())) << "frame " << f;
    if (index.size() == frames[f].positions.size()) {
      for (uint32_t j = 0; j < index.size(); ++j)
        ASSERT_EQ(index[j], j) << "frame " << f;
      EXPECT_EQ(dec.triangles, frames[f].triangles)
          << "frame " << f << ": triangles not in the input's order and rotation";
    }
  }
  EXPECT_EQ(r.coded.vertexFrames, vertexFrames);
  EXPECT_EQ(r.coded.headerBytes + r.coded.iMeshBytes + r.coded.orderBytes + r.coded.attributeBytes +
                r.coded.pMeshBytes,
            r.coded.stream.size());
}

}  // namespace test
}  // namespace tdvo
