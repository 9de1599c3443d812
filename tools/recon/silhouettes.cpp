#include "tools/recon/silhouettes.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/background_segm.hpp>
#include <opencv2/video/tracking.hpp>

#include "common/core/error.h"

namespace tdvo {

namespace {

// An Image as a cv::Mat header over the same pixels (no copy).
cv::Mat asMat(const Image& image) {
  return cv::Mat(image.height, image.width, CV_8UC(image.channels),
                 const_cast<uint8_t*>(image.pixels.data()));
}

// The image as 3-channel BGR-ordered data for OpenCV (the channel order does not matter to the
// background model, only its consistency).
cv::Mat colourMat(const Image& image) {
  if (image.channels == 3) return asMat(image).clone();
  return asMat(convertChannels(image, 3)).clone();
}

Image fromMask(const cv::Mat& mask) {
  Image out(mask.cols, mask.rows, 1);
  for (int y = 0; y < mask.rows; ++y) {
    const uint8_t* row = mask.ptr<uint8_t>(y);
    for (int x = 0; x < mask.cols; ++x)
      out.at(x, y) = row[x] ? 255 : 0;
  }
  return out;
}

cv::Mat disc(int radius) {
  return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
}

}  // namespace

Image thresholdSilhouette(const Image& image, const ThresholdRecipe& recipe) {
  check(!image.empty(), "threshold silhouette: empty image");
  const Image grey = convertChannels(image, 1);
  cv::Mat mask(grey.height, grey.width, CV_8U);
  const double level = recipe.threshold * 255;
  for (int y = 0; y < grey.height; ++y)
    for (int x = 0; x < grey.width; ++x)
      mask.at<uint8_t>(y, x) = grey.at(x, y) > level ? 255 : 0;
  if (recipe.dilate > 0) cv::dilate(mask, mask, disc(recipe.dilate));
  if (recipe.erode > 0) cv::erode(mask, mask, disc(recipe.erode));
  return fromMask(mask);
}

struct BackgroundSegmenter::State {
  BackgroundOptions options;
  cv::Ptr<cv::BackgroundSubtractorMOG2> model;
  cv::KalmanFilter kalman{8, 4, 0, CV_64F};  // state: cx cy w h and their velocities
  bool tracking = false;
  std::array<double, 4> region = {-1, -1, -1, -1};
};

BackgroundSegmenter::BackgroundSegmenter(const BackgroundOptions& options)
    : state_(std::make_unique<State>()) {
  state_->options = options;
  state_->model = cv::createBackgroundSubtractorMOG2(options.history, options.varThreshold,
                                                     options.detectShadows);
  cv::KalmanFilter& k = state_->kalman;
  cv::setIdentity(k.transitionMatrix);
  for (int i = 0; i < 4; ++i)
    k.transitionMatrix.at<double>(i, i + 4) = 1;
  k.measurementMatrix = cv::Mat::zeros(4, 8, CV_64F);
  for (int i = 0; i < 4; ++i)
    k.measurementMatrix.at<double>(i, i) = 1;
  cv::setIdentity(k.processNoiseCov, cv::Scalar::all(options.processNoise * options.processNoise));
  cv::setIdentity(k.measurementNoiseCov,
                  cv::Scalar::all(options.measurementNoise * options.measurementNoise));
}

BackgroundSegmenter::~BackgroundSegmenter() = default;
BackgroundSegmenter::BackgroundSegmenter(BackgroundSegmenter&&) noexcept = default;

void BackgroundSegmenter::learnBackground(const Image& frame) {
  cv::Mat foreground;
  state_->model->apply(colourMat(frame), foreground, -1);
}

std::array<double, 4> BackgroundSegmenter::region() const {
  return state_->region;
}

Image BackgroundSegmenter::segment(const Image& frame) {
  State& s = *state_;
  const BackgroundOptions& o = s.options;
  const cv::Mat image = colourMat(frame);

  // 1. Foreground against the model, without updating it; shadows (127) are background.
  cv::Mat raw;
  s.model->apply(image, raw, 0);
  cv::Mat foreground = raw == 255;
  // 2. Morphological clean-up.
  if (o.openRadius > 0)
    cv::morphologyEx(foreground, foreground, cv::MORPH_OPEN, disc(o.openRadius));
  if (o.closeRadius > 0)
    cv::morphologyEx(foreground, foreground, cv::MORPH_CLOSE, disc(o.closeRadius));

  // 3. Blobs, the Kalman-filtered region, and the blobs that touch it.
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(foreground, labels, stats, centroids, 8);
  const double minArea = o.minBlobArea * frame.width * frame.height;
  cv::Rect2d predicted;
  if (s.tracking) {
    const cv::Mat p = s.kalman.predict();
    const double cx = p.at<double>(0), cy = p.at<double>(1);
    const double w = std::max(1.0, p.at<double>(2)), h = std::max(1.0, p.at<double>(3));
    predicted = cv::Rect2d(cx - w / 2 - o.regionMargin * w, cy - h / 2 - o.regionMargin * h,
                           w * (1 + 2 * o.regionMargin), h * (1 + 2 * o.regionMargin));
  }
  // Before the object has been found, its largest blob starts the track.
  int largest = 0;
  for (int label = 1; label < count; ++label)
    if (stats.at<int>(label, cv::CC_STAT_AREA) >= minArea &&
        (largest == 0 ||
         stats.at<int>(label, cv::CC_STAT_AREA) > stats.at<int>(largest, cv::CC_STAT_AREA)))
      largest = label;
  std::vector<bool> keep(static_cast<size_t>(count), false);
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (int label = 1; label < count; ++label) {
    if (stats.at<int>(label, cv::CC_STAT_AREA) < minArea) continue;
    if (!s.tracking && label != largest) continue;
    const cv::Rect2d box(
        stats.at<int>(label, cv::CC_STAT_LEFT), stats.at<int>(label, cv::CC_STAT_TOP),
        stats.at<int>(label, cv::CC_STAT_WIDTH), stats.at<int>(label, cv::CC_STAT_HEIGHT));
    // A blob mostly outside the predicted region is something else (a lighting change, a
    // reflection): letting it in would drag the region after it.
    if (s.tracking && (box & predicted).area() < 0.5 * box.area()) continue;
    keep[static_cast<size_t>(label)] = true;
    x0 = std::min(x0, box.x);
    y0 = std::min(y0, box.y);
    x1 = std::max(x1, box.x + box.width - 1);
    y1 = std::max(y1, box.y + box.height - 1);
  }
  const bool measured = x0 <= x1;
  if (measured) {
    const cv::Mat z =
        (cv::Mat_<double>(4, 1) << 0.5 * (x0 + x1), 0.5 * (y0 + y1), x1 - x0 + 1, y1 - y0 + 1);
    if (!s.tracking) {
      s.kalman.statePost = cv::Mat::zeros(8, 1, CV_64F);
      z.copyTo(s.kalman.statePost.rowRange(0, 4));
      cv::setIdentity(s.kalman.errorCovPost,
                      cv::Scalar::all(o.measurementNoise * o.measurementNoise));
      s.tracking = true;
    } else {
      s.kalman.correct(z);
    }
  }
  cv::Mat mask = cv::Mat::zeros(foreground.size(), CV_8U);
  if (s.tracking) {
    const cv::Mat& e = s.kalman.statePost;
    const double cx = e.at<double>(0), cy = e.at<double>(1);
    const double w = std::max(1.0, e.at<double>(2)), h = std::max(1.0, e.at<double>(3));
    s.region = {cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2};
    const int rx0 = std::max(0, static_cast<int>(std::floor(cx - w / 2 - o.regionMargin * w)));
    const int ry0 = std::max(0, static_cast<int>(std::floor(cy - h / 2 - o.regionMargin * h)));
    const int rx1 =
        std::min(frame.width - 1, static_cast<int>(std::ceil(cx + w / 2 + o.regionMargin * w)));
    const int ry1 =
        std::min(frame.height - 1, static_cast<int>(std::ceil(cy + h / 2 + o.regionMargin * h)));
    for (int y = ry0; y <= ry1; ++y)
      for (int x = rx0; x <= rx1; ++x)
        if (keep[static_cast<size_t>(labels.at<int>(y, x))]) mask.at<uint8_t>(y, x) = 255;

    // 4. Update the model everywhere but in the object's region.
    if (o.learningRate > 0 && rx0 <= rx1 && ry0 <= ry1) {
      cv::Mat background;
      s.model->getBackgroundImage(background);
      cv::Mat update = image.clone();
      if (background.size() == update.size() && background.type() == update.type()) {
        const cv::Rect r(rx0, ry0, rx1 - rx0 + 1, ry1 - ry0 + 1);
        background(r).copyTo(update(r));
      }
      cv::Mat ignored;
      s.model->apply(update, ignored, o.learningRate);
    }
  }
  return fromMask(mask);
}

double maskIoU(const Image& a, const Image& b) {
  check(a.width == b.width && a.height == b.height, "mask IoU: masks of different sizes");
  size_t both = 0, either = 0;
  const size_t n = static_cast<size_t>(a.width) * static_cast<size_t>(a.height);
  for (size_t i = 0; i < n; ++i) {
    const bool x = a.pixels[i * static_cast<size_t>(a.channels)] >= 128;
    const bool y = b.pixels[i * static_cast<size_t>(b.channels)] >= 128;
    both += x && y;
    either += x || y;
  }
  return either == 0 ? 1.0 : double(both) / double(either);
}

}  // namespace tdvo
