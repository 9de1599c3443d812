// Geometry metrics: how far a decoded mesh (or mesh sequence) is from its reference.
//
// Three families, documented with their formulas and sources in docs/metrics.md:
//  - surface distances between meshes of arbitrary topology: the symmetric point-to-surface
//    Hausdorff distance (max and mean), sampled at the vertices of each mesh against the
//    triangles of the other;
//  - vertex errors between meshes with the same vertex count and a known vertex correspondence:
//    vertex RMSE, the temporal average error D_A and the KG error (Karni & Gotsman 2004);
//  - edge errors between sequences with the same connectivity and vertex order: STED, the
//    spatio-temporal edge difference (Váša & Skala 2011).
// Decoded 3DVO frames keep the input's vertex order (identity correspondence); for coders that
// reorder vertices, nearestVertexCorrespondence recovers a correspondence from the positions.
//
// Texture metrics (the end of this file): squared errors and PSNR between a camera's original
// RGB frame and the decoded one, in BT.601 Y'CbCr computed per pixel, over the object's shape
// (object PSNR) or over a rectangle such as the texture box (docs/metrics.md, "Texture metrics").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "common/core/mesh.h"
#include "common/views/image.h"

namespace tdvo {

// Squared Euclidean distance from `p` to the closest point of the (closed, filled) triangle
// abc. Degenerate triangles (zero area) are treated as the union of their edges.
double pointTriangleSquaredDistance(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c);

// A bounding volume hierarchy over the triangles of a mesh, answering "how far is this point
// from the surface" in about O(log T) instead of O(T). The mesh is copied; it may be destroyed
// after construction. Throws Error when the mesh has no triangles or a triangle refers to a
// vertex that does not exist.
class SurfaceIndex {
 public:
  explicit SurfaceIndex(const Mesh& mesh);

  // Squared distance from `p` to the closest point of any triangle.
  double squaredDistance(const Vec3d& p) const;
  // The same, faster for a run of nearby points: `hint` names a triangle (in the index's own
  // numbering) to try first, and is set to the nearest triangle found. Start with 0.
  double squaredDistance(const Vec3d& p, uint32_t& hint) const;

  size_t triangleCount() const { return corners_.size(); }

 private:
  struct Node {
    Vec3d lo, hi;    // bounds of every triangle below the node
    uint32_t first;  // leaf: first triangle in corners_; inner: index of the right child
    uint32_t count;  // leaf: number of triangles; inner: 0 (the left child is the next node)
  };
  uint32_t build(std::vector<uint32_t>& order, std::vector<Vec3d>& centroids, size_t begin,
                 size_t end, const std::vector<std::array<Vec3d, 3>>& triangles);

  std::vector<Node> nodes_;
  std::vector<std::array<Vec3d, 3>> corners_;  // triangle corners in leaf order
};

// Distances from the sample points of one mesh to the surface of another (one direction).
struct DirectedSurfaceDistance {
  double max = 0;      // largest sample distance: the one-sided Hausdorff distance
  double mean = 0;     // arithmetic mean of the sample distances, each sample weighted 1
  size_t samples = 0;  // number of sample points
};

// The sample points of `from` (its vertices referenced by at least one triangle, each once)
// against the surface of `to`.
DirectedSurfaceDistance directedSurfaceDistance(const Mesh& from, const SurfaceIndex& to);

// Both directions between a reference and a test mesh.
struct SurfaceDistance {
  DirectedSurfaceDistance referenceToTest, testToReference;
  // Symmetric Hausdorff distance: the larger one-sided maximum.
  double hausdorff() const;
  // Symmetric mean distance: the larger one-sided mean (the same convention as the maximum).
  double mean() const;
};

SurfaceDistance surfaceDistance(const Mesh& reference, const Mesh& test);

// Root mean square of the Euclidean vertex errors ||reference[i] - test[i]||, i.e.
// sqrt(1/V sum_i ||r_i - t_i||^2). Both lists in the same vertex order. Throws Error when the
// counts differ or are zero.
double vertexRmse(const std::vector<Vec3d>& reference, const std::vector<Vec3d>& test);

// Vertex errors of a sequence, accumulated frame by frame (the frames need not be held in
// memory together). All frames must have the same vertex count V; F is the number of frames.
class SequenceErrorAccumulator {
 public:
  // Adds one frame: reference and test positions in the same vertex order. Throws Error when
  // the counts differ from each other or from the earlier frames, or are zero.
  void addFrame(const std::vector<Vec3d>& reference, const std::vector<Vec3d>& test);

  int frameCount() const { return frames_; }
  size_t vertexCount() const { return vertices_; }

  // D_A = 1/(F V) sum_f sum_i ||a_fi - ã_fi||: the mean Euclidean vertex error over all frames
  // and vertices, in the units of the positions.
  double temporalAverageError() const;
  // sqrt(1/(F V) sum_f sum_i ||a_fi - ã_fi||^2).
  double vertexRmse() const;
  // KG = 100 ||A - Ã||_F / ||A - E(A)||_F, where A is the 3V x F matrix of reference
  // trajectories, Ã the test one and E(A) holds in each column the centroid of that reference
  // frame (the mean of its V positions), repeated for every vertex. Throws Error when the
  // reference has no spread about its centroids (the denominator is zero).
  double kgError() const;

 private:
  int frames_ = 0;
  size_t vertices_ = 0;
  double sumError_ = 0;          // sum of ||a - ã||
  double sumSquaredError_ = 0;   // sum of ||a - ã||^2 (the squared numerator of KG)
  double sumSquaredSpread_ = 0;  // sum of ||a - centroid_f||^2 (the squared denominator of KG)
};

// Whole-sequence shorthands for SequenceErrorAccumulator (frames[f][i] = vertex i of frame f).
double temporalAverageError(const std::vector<std::vector<Vec3d>>& reference,
                            const std::vector<std::vector<Vec3d>>& test);
double kgError(const std::vector<std::vector<Vec3d>>& reference,
               const std::vector<std::vector<Vec3d>>& test);

// ---- STED, the spatio-temporal edge difference ----
// (L. Váša, V. Skala, "A perception correlated comparison method for dynamic meshes", IEEE
// TVCG 17(2), 2011). Formulas, parameters and where each comes from: docs/metrics.md, "STED".
// It needs the same connectivity and vertex order on both sides (3DVO's decoded frames have
// them): every frame of both sequences has the first reference frame's triangle list.

// The scale parameters. Lengths are fractions of the diagonal D of the first reference frame's
// bounding box (the object's size, not that of its path through the scene).
struct StedParams {
  // w: the spatial neighbourhood of a vertex is the vertices within along-edge (graph geodesic)
  // distance w·D of it on the first reference frame, always with its 1-ring; its edges are the
  // edges between them. 0 = the 1-ring alone.
  double width = 0.0;
  // dt: a temporal edge joins a vertex's positions in frames f and f+1; its length is that of
  // the 4D vector (displacement, dt·D). Must be positive.
  double timeStep = 0.3;
  // c: STED = sqrt(STED_s² + c²·STED_t²).
  double temporalWeight = 1.0;
  // The neighbourhoods are kept for every frame: at most this many edges in all (256 MiB as
  // uint32; a wide w on a large mesh needs up to the square of its size). More is an Error
  // from the first addFrame.
  size_t maxNeighbourhoodEdges = size_t{1} << 26;
};

// STED accumulated frame by frame (the frames need not be held in memory together).
class StedAccumulator {
 public:
  explicit StedAccumulator(const StedParams& params = {});

  // Adds frame f of both sequences. Throws Error when the test and the reference differ in
  // vertex count or triangle list, when either differs from the first frame's, or (first
  // frame) when the mesh has no edge of non-zero length or a triangle names a missing vertex.
  void addFrame(const Mesh& reference, const Mesh& test);

  int frameCount() const { return frames_; }
  // STED_s: the mean over frames and vertices of the local (length-weighted) standard deviation
  // of the relative edge-length differences in the vertex's neighbourhood.
  double spatial() const;
  // STED_t: the mean over frame pairs and vertices of the relative temporal-edge-length
  // differences. Absent for a single frame.
  std::optional<double> temporal() const;
  // sqrt(STED_s² + c²·STED_t²); absent for a single frame.
  std::optional<double> combined() const;
  // The spatial part of the last frame added.
  double lastFrameSpatial() const { return lastSpatial_; }

 private:
  void prepare(const Mesh& reference);

  StedParams params_;
  int frames_ = 0;
  double timeLength_ = 0;  // dt·D
  std::vector<Triangle> triangles_;
  size_t vertexCount_ = 0;
  std::vector<std::array<uint32_t, 2>> edges_;  // each undirected edge once
  // Vertices with at least one edge, and the edges of each one's neighbourhood (CSR).
  std::vector<uint32_t> vertices_, neighbourhoodStart_, neighbourhoodEdges_;
  std::vector<Vec3d> previousReference_, previousTest_;
  double sumSpatial_ = 0, sumTemporal_ = 0, lastSpatial_ = 0;
  size_t spatialTerms_ = 0, temporalTerms_ = 0;
};

// Whole-sequence shorthand: the accumulator fed with every frame.
StedAccumulator sted(const std::vector<Mesh>& reference, const std::vector<Mesh>& test,
                     const StedParams& params = {});

// A vertex correspondence from positions: result[i] is the reference vertex matched to test
// vertex i; it is a one-to-one map (a permutation). Each test vertex is matched to its nearest
// reference vertex; when several test vertices have the same nearest reference vertex, the one
// closest to it keeps it and the others take their nearest reference vertex still free. Test
// vertices are handled in order of increasing distance to their nearest reference vertex (ties:
// lower test index first); equally distant reference vertices go to the lower index. Throws
// Error when the counts differ or are zero.
std::vector<uint32_t> nearestVertexCorrespondence(const std::vector<Vec3d>& reference,
                                                  const std::vector<Vec3d>& test);

// The test positions in reference order: result[correspondence[i]] = test[i]. Throws Error when
// the sizes differ or `correspondence` is not a permutation.
std::vector<Vec3d> inReferenceOrder(const std::vector<Vec3d>& test,
                                    const std::vector<uint32_t>& correspondence);

// An axis-aligned bounding box grown point by point; its diagonal is the length unit of
// distances reported relative to the reference.
struct BoundingBox {
  Vec3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity()};
  Vec3d hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
           -std::numeric_limits<double>::infinity()};
  void extend(const std::vector<Vec3d>& points);
  // Length of the diagonal; 0 for an empty box.
  double diagonal() const;
};

// ---- Texture metrics ----

// The Y'CbCr of one 8-bit RGB pixel, per ITU-R BT.601 (K_R = 0.299, K_B = 0.114) in limited
// range (Y' 16..235, Cb and Cr 16..240 for RGB in 0..255), unrounded: the same matrix and range
// as the texture coder's conversion (common/media/yuv.h), but per pixel, without chroma subsampling
// and without rounding to integers.
std::array<double, 3> rgbToYcbcr601(uint8_t r, uint8_t g, uint8_t b);

// Squared errors of Y', Cb and Cr summed over a set of pixels, mergeable across pictures.
struct PictureError {
  uint64_t pixels = 0;                    // pixels counted
  std::array<double, 3> sumSquared = {};  // Y', Cb, Cr: sum of (reference − test)²

  void add(const PictureError& other);
  // Mean squared error of component c (0 = Y', 1 = Cb, 2 = Cr); absent without pixels.
  std::optional<double> mse(int c) const;
  // 10·log10(255² / MSE) dB; +infinity for MSE 0; absent without pixels.
  std::optional<double> psnr(int c) const;
  // (6·PSNR_Y + PSNR_Cb + PSNR_Cr) / 8, the weighting of the JCT-VC / JVET common test
  // conditions; absent without pixels, +infinity when a component's PSNR is.
  std::optional<double> yuvPsnr() const;
};

// The errors between a reference and a test image (RGB or RGBA, only R, G, B compared; same size)
// over the pixels where `mask` (one channel, same size) is non-zero. Throws Error when the sizes
// differ or an image has fewer than 3 channels.
PictureError maskedPictureError(const Image& reference, const Image& test, const Image& mask);

// The same over the rectangle [x0, x1) × [y0, y1), clipped to the images.
PictureError regionPictureError(const Image& reference, const Image& test, int x0, int y0, int x1,
                                int y1);

}  // namespace tdvo
