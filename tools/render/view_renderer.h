// The view-dependent renderer: a 3D video object (a mesh plus the N camera images of the same
// frame) seen from a virtual camera. docs/rendering.md describes it in full.
//
// Per pixel of the virtual camera covered by the mesh (the rasteriser's z-buffer), the surface
// point P is looked up in every camera i:
//   - P must be in front of camera i;
//   - texture sample: the bilinear footprint of P's projection, four texels; a texel takes part
//     when it lies inside the image, inside the camera's mask (when it has one) and is not
//     hidden: camera i's depth map there is not nearer than P's depth z_i by more than the
//     tolerance, z_i ≤ D_i(texel) · (1 + depthTolerance). The sample is the bilinear average over
//     the texels that take part (their bilinear weights renormalised);
//   - camera i sees P when at least one texel with non-zero bilinear weight takes part.
// The colour is Σ w_i · sample_i over the cameras that see P, with the view-dependent weights of
// tools/eval/view_weights.h: `Blending::angle` (viewWeights) or `Blending::ulr` (ulrWeights: a
// resolution penalty and a factor falling to 0 at camera i's silhouette and depth edges, from
// the per-camera edge distance maps of FrameViews). Where no camera sees P the fallback applies:
// `fill` colours the pixel from the blended pixels around it in the rendered image (push-pull);
// `nearest` takes the sample of the camera with the largest weight among those where P projects
// inside the image and inside the mask, ignoring the depth test (hidden surfaces get the colour
// of what hides them rather than a hole), and where even that fails the flat fallback colour;
// `colour` uses the flat colour right away.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "common/core/mesh.h"
#include "common/media/dataset.h"
#include "common/views/camera.h"
#include "common/views/image.h"

namespace tdvo {

// Which directions the view-dependent weights compare.
enum class ViewDirection {
  axis,  // camera i's optical axis vs the virtual camera's optical axis (the source paper)
  ray,   // per surface point P: unit(C_i − P) vs unit(C_virtual − P), C the camera centres
};

// How the cameras that see a point are weighted (docs/rendering.md, "Blending").
enum class Blending {
  angle,  // w_i ∝ sin(θ_i / 2)^(−k) (tools/eval/view_weights.h)
  ulr,    // unstructured-lumigraph style: the angle term with a resolution penalty, times a
          // factor falling to 0 at the silhouette and depth edges of camera i
};

// Where no camera sees a point: `nearest` camera ignoring the depth test, the flat `colour`, or
// `fill` from the neighbouring blended pixels of the rendered image (push-pull).
enum class Fallback { nearest, colour, fill };

// Edges of a camera's shape are searched up to this distance (pixels): EdgeWidth's maximum.
constexpr int kMaxEdgeWidth = 16;
// A depth edge lies between 4-neighbours of a camera's shape whose depths differ by more than
// this share of the nearer depth.
constexpr double kEdgeDepthJump = 0.05;

struct RenderOptions {
  Blending blending = Blending::ulr;
  ViewDirection direction = ViewDirection::axis;
  double sharpness = 4;          // k of the weights (view_weights.h)
  double resolutionPenalty = 1;  // ulr: β of s_i · (1 + β · max(0, r_i − 1))
  double edgeWidth = 8;          // ulr: pixels over which a camera's weight rises from its edges
  double depthTolerance = 0.01;  // relative depth tolerance of the visibility test
  Fallback fallback = Fallback::fill;
  std::array<uint8_t, 3> fallbackColour = {128, 128, 128};  // where no camera has a sample
  std::array<uint8_t, 3> background = {0, 0, 0};  // pixels the mesh does not cover (alpha 0)
};

// Everything the renderer needs of one frame: the mesh, and per camera its calibration, RGB
// image, optional mask (grey, 255 inside; empty: the whole image counts) and the depth map of the
// mesh (renderDepth).
struct FrameViews {
  Mesh mesh;
  std::vector<Camera> cameras;
  std::vector<Image> images;  // RGB
  std::vector<Image> masks;   // grey or empty
  std::vector<std::vector<float>> depth;
  // Per camera and pixel the Euclidean distance (pixels) to the nearest edge pixel of the
  // camera's shape, at most kMaxEdgeWidth (edgeDistances).
  std::vector<std::vector<float>> edgeDistance;
};

// The edge distance map of one camera. The shape is the pixels with a finite depth inside the
// mask (when there is one); an edge pixel is a shape pixel with a 4-neighbour inside the image
// that is outside the shape or whose depth differs from its own by more than kEdgeDepthJump
// times the smaller of the two. Value: the distance from the pixel centre to the nearest edge
// pixel centre, capped at kMaxEdgeWidth (0 on edge pixels; pixels outside the shape have theirs
// too). O(pixels · kMaxEdgeWidth), however many edges there are.
std::vector<float> edgeDistances(const std::vector<float>& depth, const Image& mask, int width,
                                 int height);

// Reads frame index `frame` of a dataset (its meshes, images, masks) and renders the depth maps.
// The dataset must have meshes.
FrameViews loadFrameViews(const Dataset& dataset, std::vector<CameraFrames>& frames, int frame);
// Builds the views from given parts (depth maps rendered here).
FrameViews makeFrameViews(Mesh mesh, std::vector<Camera> cameras, std::vector<Image> images,
                          std::vector<Image> masks);

struct RenderStats {
  size_t covered = 0;          // pixels the mesh covers
  size_t blended = 0;          // of those, pixels seen by at least one camera
  size_t fallbackNearest = 0;  // pixels from the nearest camera, ignoring the depth test
  size_t fallbackColour = 0;   // pixels in the flat fallback colour
  size_t fallbackFill = 0;     // pixels filled from the neighbouring blended pixels
  RenderStats& operator+=(const RenderStats& o);
};

// Where a rendered pixel's colour came from (the values of renderView's `sources` map).
enum PixelSource : uint8_t {
  kSourceEmpty = 0,    // the mesh does not cover the pixel
  kSourceBlended = 1,  // blended from the cameras that see the point
  kSourceNearest = 2,  // fallback: the nearest camera, depth test ignored
  kSourceColour = 3,   // fallback: the flat colour
  kSourceFill = 4,     // fallback: filled from the neighbouring blended pixels
};
// Whether a PixelSource value is one of the fallbacks (no camera sees the point).
inline bool isFallback(uint8_t source) {
  return source == kSourceNearest || source == kSourceColour || source == kSourceFill;
}

// Renders the frame from `view` (any camera model, distortion included) as an RGBA image: alpha
// 255 where the mesh covers the pixel, 0 (and the background colour) elsewhere. `useCamera`
// (empty: all) selects the cameras whose textures may be used, e.g. all but one for the
// leave-one-out test. `stats` (when given) is added to; `sources` (when given) becomes a grey
// image of PixelSource values.
Image renderView(const FrameViews& views, const Camera& view, const RenderOptions& options,
                 const std::vector<bool>& useCamera = {}, RenderStats* stats = nullptr,
                 Image* sources = nullptr);

// PSNR (dB, peak 255) of the RGB channels of `test` against `reference` over the pixels where
// `mask` is non-zero, from the summed squared error and sample count (so results of several
// images can be pooled): see SquaredError.
struct SquaredError {
  double sum = 0;    // Σ (test − reference)² over the counted samples
  size_t count = 0;  // samples counted (3 per pixel)
  SquaredError& operator+=(const SquaredError& o);
  double psnr() const;  // +infinity when sum is 0; NaN when nothing was counted
};
SquaredError maskedSquaredError(const Image& test, const Image& reference, const Image& mask);

}  // namespace tdvo
