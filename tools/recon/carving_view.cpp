#include "tools/recon/carving_view.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/core/error.h"

namespace tdvo {

CanvasMap CanvasMap::build(const Camera& camera) {
  check(camera.width >= 2 && camera.height >= 2,
        "camera '" + camera.name + "': images must be at least 2 x 2 pixels for carving");
  CanvasMap map;
  map.sourceWidth = camera.width;
  map.sourceHeight = camera.height;
  map.pinhole = camera.withoutDistortion();
  if (camera.distortion.isZero()) return map;

  // The undistorted positions of the image border bound the canvas.
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  auto extend = [&](double x, double y) {
    const Vec2d u = camera.undistortPixel({x, y});
    for (int k = 0; k < 2; ++k) {
      lo[k] = std::min(lo[k], u[k]);
      hi[k] = std::max(hi[k], u[k]);
    }
  };
  const double w = camera.width, h = camera.height;
  for (int i = 0; i < camera.width; ++i) {
    extend(i, -0.5);
    extend(i, h - 0.5);
  }
  for (int j = 0; j < camera.height; ++j) {
    extend(-0.5, j);
    extend(w - 0.5, j);
  }
  lo[0] = std::max(lo[0], -w);
  lo[1] = std::max(lo[1], -h);
  hi[0] = std::min(hi[0], 2 * w);
  hi[1] = std::min(hi[1], 2 * h);
  const int x0 = static_cast<int>(std::floor(lo[0])), y0 = static_cast<int>(std::floor(lo[1]));
  const int x1 = static_cast<int>(std::ceil(hi[0])), y1 = static_cast<int>(std::ceil(hi[1]));
  map.pinhole.width = x1 - x0 + 1;
  map.pinhole.height = y1 - y0 + 1;
  map.pinhole.cx = camera.cx - x0;
  map.pinhole.cy = camera.cy - y0;

  // Beyond the lens model's fold distortPixel would fold back into the image: such canvas
  // pixels stay unknown.
  const double foldRadius = 0.999 * monotonicRadius(camera.distortion);
  map.source.assign(static_cast<size_t>(map.pinhole.width) * map.pinhole.height, -1);
  for (int v = 0; v < map.pinhole.height; ++v)
    for (int u = 0; u < map.pinhole.width; ++u) {
      const Vec2d undistorted = {u + static_cast<double>(x0), v + static_cast<double>(y0)};
      const Vec2d n = camera.pixelToNormalised(undistorted);
      if (std::hypot(n[0], n[1]) >= foldRadius) continue;
      const Vec2d d = camera.distortPixel(undistorted);
      const long i = std::lround(d[0]), j = std::lround(d[1]);
      if (i < 0 || j < 0 || i >= camera.width || j >= camera.height) continue;
      map.source[static_cast<size_t>(v) * map.pinhole.width + u] =
          static_cast<int32_t>(j * camera.width + i);
    }
  return map;
}

CarvingView::CarvingView(const CanvasMap& map, const Image& mask)
    : pinhole_(map.pinhole), width_(map.pinhole.width), height_(map.pinhole.height) {
  check(mask.width == map.sourceWidth && mask.height == map.sourceHeight && mask.channels >= 1,
        "silhouette of camera '" + pinhole_.name + "' has the wrong size");
  focal_ = 0.5 * (pinhole_.fx + pinhole_.fy);
  const size_t n = static_cast<size_t>(width_) * height_;
  object_.resize(n);
  const size_t channels = static_cast<size_t>(mask.channels);
  if (map.source.empty()) {
    for (size_t i = 0; i < n; ++i)
      object_[i] = mask.pixels[i * channels] >= 128 ? 1 : 0;
  } else {
    known_.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const int32_t s = map.source[i];
      known_[i] = s >= 0 ? 1 : 0;
      object_[i] = s < 0 || mask.pixels[static_cast<size_t>(s) * channels] >= 128 ? 1 : 0;
    }
  }

  cv::Mat objectMat(height_, width_, CV_8U, object_.data());
  cv::Mat integral;
  if (known_.empty()) {
    cv::integral(objectMat, integral, CV_32S);
  } else {
    // Object pixels the camera saw; unknown ones are counted separately.
    cv::Mat knownMat(height_, width_, CV_8U, known_.data());
    cv::Mat knownObject = objectMat & knownMat, knownSums;
    cv::integral(knownObject, integral, CV_32S);
    cv::integral(knownMat, knownSums, CV_32S);
    knownIntegral_.assign(knownSums.begin<int32_t>(), knownSums.end<int32_t>());
  }
  integral_.assign(integral.begin<int32_t>(), integral.end<int32_t>());

  // Signed distance: an object pixel is d_in − ½ from the boundary, d_in its distance to the
  // nearest background pixel centre; a background pixel −(d_out − ½). Where one kind of pixel
  // is missing altogether the distance transform returns huge values: capped at the canvas
  // size.
  cv::Mat background = objectMat == 0, inside, outside;
  cv::distanceTransform(objectMat, inside, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::distanceTransform(background, outside, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const float cap = static_cast<float>(width_ + height_);
  signedDistance_.resize(n);
  for (int y = 0; y < height_; ++y) {
    const float* in = inside.ptr<float>(y);
    const float* out = outside.ptr<float>(y);
    for (int x = 0; x < width_; ++x) {
      const size_t i = static_cast<size_t>(y) * width_ + x;
      signedDistance_[i] =
          object_[i] ? std::min(in[x], cap) - 0.5f : -(std::min(out[x], cap) - 0.5f);
    }
  }
}

ViewVerdict CarvingView::judgeBox(const Vec3d& lo, const Vec3d& hi) const {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  int behind = 0;
  Vec3d p[8];
  for (int c = 0; c < 8; ++c) {
    p[c] = pinhole_.toCamera({c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]});
    behind += !(p[c][2] > 0);
  }
  if (behind == 8) return ViewVerdict::unseen;  // wholly behind the camera
  if (behind > 0) return ViewVerdict::partial;  // across the camera plane: no footprint
  for (int c = 0; c < 8; ++c) {
    const double x = pinhole_.fx * p[c][0] / p[c][2] + pinhole_.cx;
    const double y = pinhole_.fy * p[c][1] / p[c][2] + pinhole_.cy;
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  const double maxX = width_ - 1, maxY = height_ - 1;
  if (x1 < 0 || y1 < 0 || x0 > maxX || y0 > maxY) return ViewVerdict::unseen;
  bool clipped = x0 < 0 || y0 < 0 || x1 > maxX || y1 > maxY;
  // Pixels a bilinear lookup of any point in the rectangle can touch. The corners are clamped
  // to the image before they become integers: a corner far outside (a long focal length, a
  // box near the camera plane) is beyond any int.
  const int i0 = static_cast<int>(std::floor(std::max(x0, 0.0)));
  const int j0 = static_cast<int>(std::floor(std::max(y0, 0.0)));
  const int i1 = static_cast<int>(std::floor(std::min(x1, maxX))) + (x1 < maxX ? 1 : 0);
  const int j1 = static_cast<int>(std::floor(std::min(y1, maxY))) + (y1 < maxY ? 1 : 0);
  const size_t stride = static_cast<size_t>(width_) + 1;
  auto sum = [&](const std::vector<uint32_t>& table) {
    auto at = [&](int i, int j) { return table[static_cast<size_t>(j) * stride + i]; };
    return at(i1 + 1, j1 + 1) - at(i0, j1 + 1) - at(i1 + 1, j0) + at(i0, j0);
  };
  const uint32_t area = static_cast<uint32_t>(i1 - i0 + 1) * static_cast<uint32_t>(j1 - j0 + 1);
  const uint32_t object = sum(integral_);
  const uint32_t known = knownIntegral_.empty() ? area : sum(knownIntegral_);
  if (known == 0) return ViewVerdict::unseen;
  if (known < area) clipped = true;
  if (object == known) return clipped ? ViewVerdict::insideClipped : ViewVerdict::insideSeen;
  if (object == 0 && !clipped) return ViewVerdict::outside;
  return ViewVerdict::partial;
}

bool CarvingView::signedDistance(const Vec3d& world, double& distance) const {
  const Vec3d p = pinhole_.toCamera(world);
  if (!(p[2] > 0)) return false;
  const double x = pinhole_.fx * p[0] / p[2] + pinhole_.cx;
  const double y = pinhole_.fy * p[1] / p[2] + pinhole_.cy;
  if (!(x >= 0 && y >= 0 && x <= width_ - 1 && y <= height_ - 1)) return false;
  const int i = std::min(static_cast<int>(x), width_ - 2);
  const int j = std::min(static_cast<int>(y), height_ - 2);
  const double a = x - i, b = y - j;
  const size_t at = static_cast<size_t>(j) * width_ + i;
  if (!known_.empty() &&
      !(known_[at] && known_[at + 1] && known_[at + width_] && known_[at + width_ + 1]))
    return false;
  const float* row = &signedDistance_[at];
  const double top = (1 - a) * row[0] + a * row[1];
  const double bottom = (1 - a) * row[width_] + a * row[width_ + 1];
  distance = ((1 - b) * top + b * bottom) * p[2] / focal_;
  return true;
}

}  // namespace tdvo
