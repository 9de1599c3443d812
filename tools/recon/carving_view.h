// One camera's silhouette prepared for shape-from-silhouette: what the octree carving and the
// surface extraction ask of a view.
//
// - Lens distortion is removed once, up front: the mask is resampled into a pinhole camera
//   whose canvas is enlarged to hold the whole undistorted field of view. Under a pinhole
//   projection the image of a box is the convex hull of its projected corners, so the bounding
//   rectangle of the corners is a conservative footprint of a cell.
// - Pixels the camera did not see (outside its original image, or beyond the lens model's fold)
//   are *unknown*: a point whose projection touches one is not seen by the view, just like a
//   point projecting outside the canvas. A view never carves what it did not see.
// - An integral image of the object pixels answers "how many object pixels does this
//   rectangle hold" in four reads (the conservative cell test), and a signed distance field in
//   pixels (positive inside, negative outside, zero half-way between a pixel centre inside and
//   one outside) gives the surface its sub-voxel position.
#pragma once

#include <cstdint>
#include <vector>

#include "common/views/camera.h"
#include "common/views/image.h"

namespace tdvo {

// How one view judges a box (a cell of the octree).
enum class ViewVerdict : uint8_t {
  outside,        // the box projects into the image onto background only: carve it
  insideSeen,     // projects into the image onto object pixels only
  insideClipped,  // partly outside the image; the part inside shows object only
  unseen,         // projects completely outside the image
  partial,        // object and background (or the box reaches behind the camera)
};

// Where each pixel of the enlarged pinhole canvas comes from in the camera's own image; built
// once per camera and shared by every frame.
struct CanvasMap {
  Camera pinhole;  // no distortion; width/height are the canvas size
  int sourceWidth = 0, sourceHeight = 0;
  std::vector<int32_t> source;  // canvas pixel → source pixel index, −1 when unknown; empty
                                // when the camera has no distortion (the identity)

  // The map of `camera`. The canvas holds the undistorted image of the whole original image
  // (at most three times its size in each direction).
  static CanvasMap build(const Camera& camera);
};

class CarvingView {
 public:
  // `mask`: grey silhouette (≥ 128 object) of the camera `map` was built from.
  CarvingView(const CanvasMap& map, const Image& mask);

  // The pinhole camera the view works in (the input camera without distortion, on the enlarged
  // canvas).
  const Camera& pinhole() const { return pinhole_; }
  int width() const { return width_; }
  int height() const { return height_; }

  // Judges the axis-aligned box [lo, hi]: its eight corners are projected and the pixels whose
  // centres can enter a bilinear lookup for any point of the box (the corners' bounding
  // rectangle widened to whole pixels plus one) are counted. A box judged outside (inside and
  // seen) therefore has a negative (positive) signedDistance() at every point; one judged
  // unseen has no point the view sees; one judged inside-clipped has a positive distance at
  // every point the view sees.
  ViewVerdict judgeBox(const Vec3d& lo, const Vec3d& hi) const;

  // Signed distance of a world point to the silhouette's boundary in world units at the
  // point's depth (pixels × depth / focal length), positive inside. Returns false when the
  // point is not seen: behind the camera, or its projection is not surrounded by four known
  // pixel centres of the canvas.
  bool signedDistance(const Vec3d& world, double& distance) const;

  // The object mask on the pinhole canvas (1 object or unknown, 0 background), for tests.
  const std::vector<uint8_t>& objectPixels() const { return object_; }
  // The canvas pixels the camera saw (1) or not (0); empty when it saw all of them.
  const std::vector<uint8_t>& knownPixels() const { return known_; }

 private:
  Camera pinhole_;
  int width_ = 0, height_ = 0;
  double focal_ = 1;                     // mean of fx and fy
  std::vector<uint8_t> object_;          // width × height, 1 object/unknown
  std::vector<uint8_t> known_;           // width × height, 1 seen; empty: all seen
  std::vector<uint32_t> integral_;       // (width+1) × (height+1) sums of known object pixels
  std::vector<uint32_t> knownIntegral_;  // (width+1) × (height+1) sums of known_ (if any)
  std::vector<float> signedDistance_;    // width × height, pixels
};

}  // namespace tdvo
