#include "tools/render/view_renderer.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <thread>

#include "common/core/error.h"
#include "common/views/rasteriser.h"
#include "tools/eval/view_weights.h"

namespace tdvo {

FrameViews makeFrameViews(Mesh mesh, std::vector<Camera> cameras, std::vector<Image> images,
                          std::vector<Image> masks) {
  check(images.size() == cameras.size(), "renderer: one image per camera is needed");
  masks.resize(cameras.size());
  FrameViews v;
  v.mesh = std::move(mesh);
  v.cameras = std::move(cameras);
  v.images = std::move(images);
  v.masks = std::move(masks);
  for (size_t i = 0; i < v.cameras.size(); ++i) {
    const Camera& c = v.cameras[i];
    check(v.images[i].width == c.width && v.images[i].height == c.height,
          "renderer: image size of camera '" + c.name + "' differs from its calibration");
    if (v.images[i].channels != 3) v.images[i] = convertChannels(v.images[i], 3);
    if (!v.masks[i].empty()) {
      check(v.masks[i].width == c.width && v.masks[i].height == c.height,
            "renderer: mask size of camera '" + c.name + "' differs from its calibration");
      if (v.masks[i].channels != 1) v.masks[i] = convertChannels(v.masks[i], 1);
    }
    v.depth.push_back(renderDepth(v.mesh, c));
  }
  return v;
}

FrameViews loadFrameViews(const Dataset& dataset, std::vector<CameraFrames>& frames, int frame) {
  std::vector<Camera> cameras;
  std::vector<Image> images, masks;
  for (size_t i = 0; i < dataset.cameras.size(); ++i) {
    cameras.push_back(dataset.cameras[i].camera);
    images.push_back(frames[i].frame(frame));
    masks.push_back(frames[i].hasMasks() ? frames[i].mask(frame) : Image());
  }
  return makeFrameViews(readDatasetMesh(dataset, frame), std::move(cameras), std::move(images),
                        std::move(masks));
}

RenderStats& RenderStats::operator+=(const RenderStats& o) {
  covered += o.covered;
  blended += o.blended;
  fallbackNearest += o.fallbackNearest;
  fallbackColour += o.fallbackColour;
  return *this;
}

namespace {

// A camera's texture sample at a surface point.
struct Sample {
  bool inImage = false;            // some texel of the footprint is inside the image and the mask
  bool seen = false;               // ... and passes the depth test
  std::array<double, 3> colour{};  // over the texels that pass the depth test
  std::array<double, 3> colourIgnoringDepth{};  // over the in-mask texels (fallback)
};

Sample sampleCamera(const FrameViews& v, size_t i, const Vec3d& point, double tolerance) {
  Sample s;
  const Camera& c = v.cameras[i];
  const Vec3d q = c.toCamera(point);
  if (!(q[2] > 0)) return s;
  const Vec2d p = c.projectCameraPoint(q);
  if (!(p[0] > -1 && p[0] < c.width && p[1] > -1 && p[1] < c.height)) return s;
  const int x0 = static_cast<int>(std::floor(p[0])), y0 = static_cast<int>(std::floor(p[1]));
  const double ax = p[0] - x0, ay = p[1] - y0;
  const Image& image = v.images[i];
  const Image& mask = v.masks[i];
  const std::vector<float>& depth = v.depth[i];
  const double limit = q[2] / (1 + tolerance);  // hidden when the depth map is nearer than this
  double seenWeight = 0, maskWeight = 0;
  for (int k = 0; k < 4; ++k) {
    const int x = x0 + (k & 1), y = y0 + (k >> 1);
    const double b = ((k & 1) ? ax : 1 - ax) * ((k >> 1) ? ay : 1 - ay);
    if (b <= 0 || x < 0 || y < 0 || x >= c.width || y >= c.height) continue;
    if (!mask.empty() && mask.at(x, y) == 0) continue;
    const size_t at = image.index(x, y);
    maskWeight += b;
    for (int ch = 0; ch < 3; ++ch)
      s.colourIgnoringDepth[static_cast<size_t>(ch)] +=
          b * image.pixels[at + static_cast<size_t>(ch)];
    if (depth[static_cast<size_t>(y) * static_cast<size_t>(c.width) + static_cast<size_t>(x)] <
        limit)
      continue;
    seenWeight += b;
    for (int ch = 0; ch < 3; ++ch)
      s.colour[static_cast<size_t>(ch)] += b * image.pixels[at + static_cast<size_t>(ch)];
  }
  if (maskWeight > 0) {
    s.inImage = true;
    for (double& x : s.colourIgnoringDepth)
      x /= maskWeight;
  }
  if (seenWeight > 0) {
    s.seen = true;
    for (double& x : s.colour)
      x /= seenWeight;
  }
  return s;
}

uint8_t toByte(double v) {
  return static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

}  // namespace

Image renderView(const FrameViews& v, const Camera& view, const RenderOptions& o,
                 const std::vector<bool>& useCamera, RenderStats* stats, Image* sources) {
  const size_t n = v.cameras.size();
  check(useCamera.empty() || useCamera.size() == n, "renderer: camera selection size mismatch");
  check(o.sharpness > 0, "renderer: the sharpness must be positive");
  check(o.depthTolerance >= 0, "renderer: the depth tolerance must not be negative");
  std::vector<size_t> cameras;
  for (size_t i = 0; i < n; ++i)
    if (useCamera.empty() || useCamera[i]) cameras.push_back(i);

  std::vector<Vec3d> axes(n), centres(n);
  for (size_t i = 0; i < n; ++i) {
    axes[i] = v.cameras[i].viewingDirection();
    centres[i] = v.cameras[i].centre();
  }
  const Vec3d viewAxis = view.viewingDirection(), viewCentre = view.centre();

  const Fragments fragments = rasterise(v.mesh, view);
  Image out(view.width, view.height, 4);
  Image source(view.width, view.height, 1, kSourceEmpty);

  // Pixels are independent: rows are shared among threads (row r to thread r mod T), which
  // changes nothing in the result.
  auto renderRows = [&](int first, int stride, RenderStats& st) {
    std::vector<double> s(n), w(n);  // per camera that sees the point
    std::vector<std::array<double, 3>> seenColour(n);
    std::vector<Sample> samples(n);
    for (int y = first; y < view.height; y += stride)
      for (int x = 0; x < view.width; ++x) {
        std::array<double, 3> colour{};
        if (fragments.triangle[fragments.index(x, y)] < 0) {
          for (int ch = 0; ch < 3; ++ch)
            out.at(x, y, ch) = o.background[static_cast<size_t>(ch)];
          continue;
        }
        ++st.covered;
        const Vec3d point = interpolate(fragments, v.mesh, v.mesh.positions, x, y);
        const Vec3d toView =
            o.direction == ViewDirection::ray ? normalized(viewCentre - point) : viewAxis;
        size_t seen = 0;
        size_t nearest = n;  // fallback: the in-image camera with the smallest angle
        double nearestS = std::numeric_limits<double>::infinity();
        for (size_t i : cameras) {
          samples[i] = sampleCamera(v, i, point, o.depthTolerance);
          if (!samples[i].inImage) continue;
          const Vec3d d =
              o.direction == ViewDirection::ray ? normalized(centres[i] - point) : axes[i];
          const double si = oneMinusCosine(d, toView);
          if (samples[i].seen) {
            s[seen] = si;
            seenColour[seen] = samples[i].colour;
            ++seen;
          } else if (si < nearestS) {
            nearestS = si;
            nearest = i;
          }
        }
        if (seen > 0) {
          ++st.blended;
          source.at(x, y) = kSourceBlended;
          viewWeights(s.data(), seen, o.sharpness, w.data());
          for (size_t j = 0; j < seen; ++j)
            for (size_t ch = 0; ch < 3; ++ch)
              colour[ch] += w[j] * seenColour[j][ch];
        } else if (o.fallback == Fallback::nearest && nearest < n) {
          ++st.fallbackNearest;
          source.at(x, y) = kSourceNearest;
          colour = samples[nearest].colourIgnoringDepth;
        } else {
          ++st.fallbackColour;
          source.at(x, y) = kSourceColour;
          for (size_t ch = 0; ch < 3; ++ch)
            colour[ch] = o.fallbackColour[ch];
        }
        for (int ch = 0; ch < 3; ++ch)
          out.at(x, y, ch) = toByte(colour[static_cast<size_t>(ch)]);
        out.at(x, y, 3) = 255;
      }
  };
  const int threads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 16u));
  std::vector<RenderStats> threadStats(static_cast<size_t>(threads));
  std::vector<std::thread> workers;
  for (int t = 1; t < threads; ++t)
    workers.emplace_back(renderRows, t, threads, std::ref(threadStats[static_cast<size_t>(t)]));
  renderRows(0, threads, threadStats[0]);
  for (std::thread& worker : workers)
    worker.join();
  if (stats)
    for (const RenderStats& st : threadStats)
      *stats += st;
  if (sources) *sources = std::move(source);
  return out;
}

SquaredError& SquaredError::operator+=(const SquaredError& o) {
  sum += o.sum;
  count += o.count;
  return *this;
}

double SquaredError::psnr() const {
  if (count == 0) return std::numeric_limits<double>::quiet_NaN();
  if (sum == 0) return std::numeric_limits<double>::infinity();
  return 10 * std::log10(255.0 * 255.0 * static_cast<double>(count) / sum);
}

SquaredError maskedSquaredError(const Image& test, const Image& reference, const Image& mask) {
  check(test.width == reference.width && test.height == reference.height &&
            mask.width == test.width && mask.height == test.height,
        "PSNR: image sizes differ");
  check(test.channels >= 3 && reference.channels >= 3 && mask.channels >= 1,
        "PSNR: colour images and a mask are needed");
  SquaredError e;
  for (int y = 0; y < test.height; ++y)
    for (int x = 0; x < test.width; ++x) {
      if (mask.at(x, y) == 0) continue;
      for (int ch = 0; ch < 3; ++ch) {
        const double d = double(test.at(x, y, ch)) - double(reference.at(x, y, ch));
        e.sum += d * d;
      }
      e.count += 3;
    }
  return e;
}

}  // namespace tdvo
