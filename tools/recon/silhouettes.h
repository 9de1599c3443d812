// Silhouette extraction: the object's mask in each camera image.
//
// - Given masks (dataset `masks`) and alpha channels (`alphaMask`) are used as they are.
// - Still sets without masks: a threshold on the luma followed by a dilation and an erosion
//   with discs (the Middlebury dino's recipe: 0.19, 10 px, 7 px).
// - Video (and stills with a background image): adaptive background subtraction. A per-pixel
//   Gaussian mixture (OpenCV's BackgroundSubtractorMOG2; shadows, which it marks separately,
//   count as background) is learned from the background frames. Each object frame is then
//     1. compared with the model (no update): foreground where no Gaussian explains the pixel;
//     2. cleaned by a morphological opening (removes speckle) and closing (fills small holes);
//     3. reduced to its blobs of at least minBlobArea that touch the object's region predicted
//        by a Kalman filter (constant-velocity model of the bounding box centre and size). The
//        blobs' bounding box corrects the filter, and everything outside the corrected region
//        (plus a margin) is dropped, so that spurious blobs and one-frame drop-outs do not
//        disturb the segmentation;
//     4. used to update the model with `learningRate`, with the object's region replaced by the
//        model's own background image, so that the model follows lighting changes around the
//        object without learning the object itself (a person sitting still would otherwise
//        fade into the background).
#pragma once

#include <array>
#include <memory>

#include "common/views/image.h"

namespace tdvo {

struct ThresholdRecipe {
  double threshold = 0.19;  // of the luma range 0 … 1: brighter pixels are object
  int dilate = 10;          // disc radius in pixels (0: none)
  int erode = 7;            // disc radius in pixels (0: none)
};

// The thresholding recipe on an 8-bit image (grey, RGB, with or without alpha; alpha ignored).
// Returns a grey mask, 255 object, 0 background.
Image thresholdSilhouette(const Image& image, const ThresholdRecipe& recipe);

struct BackgroundOptions {
  int history = 500;            // MOG2 history (frames the model remembers)
  double varThreshold = 25;     // MOG2 squared Mahalanobis distance deciding foreground
  bool detectShadows = true;    // shadows are found and counted as background
  double learningRate = 0.02;   // model update per object frame (outside the object's region)
  int openRadius = 1;           // morphological opening disc radius (0: none)
  int closeRadius = 4;          // morphological closing disc radius (0: none)
  double minBlobArea = 0.0005;  // smallest blob kept, as a fraction of the image area
  double regionMargin = 0.15;   // the object's region is its tracked box grown by this
                                // fraction of the box size on every side
  double processNoise = 2;      // Kalman: standard deviation of the box's change per frame (px)
  double measurementNoise = 4;  // Kalman: standard deviation of the measured box (px)
};

class BackgroundSegmenter {
 public:
  explicit BackgroundSegmenter(const BackgroundOptions& options);
  ~BackgroundSegmenter();
  BackgroundSegmenter(BackgroundSegmenter&&) noexcept;

  // Learns one background frame (the model's own learning rate, 1/frames seen).
  void learnBackground(const Image& frame);
  // The silhouette of an object frame (grey, 255 object); frames must come in time order.
  Image segment(const Image& frame);
  // The object's region after the last segment() (x0, y0, x1, y1 in pixels, inclusive), or
  // all −1 before the object has been found.
  std::array<double, 4> region() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Intersection over union of two masks of the same size (≥ 128 is inside); 1 when both are
// empty.
double maskIoU(const Image& a, const Image& b);

}  // namespace tdvo
