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
    v.edgeDistance.push_back(edgeDistances(v.depth.back(), v.masks[i], c.width, c.height));
  }
  return v;
}

std::vector<float> edgeDistances(const std::vector<float>& depth, const Image& mask, int width,
                                 int height) {
  const size_t w = static_cast<size_t>(width), h = static_cast<size_t>(height);
  check(depth.size() == w * h && (mask.empty() || (mask.width == width && mask.height == height)),
        "renderer: edge map sizes differ");
  auto inside = [&](size_t x, size_t y) {
    return std::isfinite(depth[y * w + x]) &&
           (mask.empty() || mask.at(static_cast<int>(x), static_cast<int>(y)) != 0);
  };
  // Edge pixels, then the exact Euclidean distance to the nearest one capped at kMaxEdgeWidth,
  // found separably in O(pixels · kMaxEdgeWidth) whatever the number of edges: per row the
  // horizontal distance to the nearest edge pixel within the cap, then per pixel the least
  // sqrt(g² + oy²) over the rows within the cap.
  std::vector<uint8_t> isEdge(w * h, 0);
  const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
  for (size_t y = 0; y < h; ++y)
    for (size_t x = 0; x < w; ++x) {
      if (!inside(x, y)) continue;
      const double d = depth[y * w + x];
      bool edge = false;
      for (int k = 0; k < 4 && !edge; ++k) {
        const long nx = static_cast<long>(x) + dx[k], ny = static_cast<long>(y) + dy[k];
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
        const size_t ux = static_cast<size_t>(nx), uy = static_cast<size_t>(ny);
        edge = !inside(ux, uy) || std::abs(depth[uy * w + ux] - d) >
                                      kEdgeDepthJump * std::min<double>(d, depth[uy * w + ux]);
      }
      isEdge[y * w + x] = edge;
    }
  const int r = kMaxEdgeWidth;
  constexpr int kFar = std::numeric_limits<int>::max() / 4;  // no edge within the cap
  std::vector<int> g(w * h, kFar);
  for (size_t y = 0; y < h; ++y) {
    int last = -kFar;  // column of the last edge pixel seen, left to right
    for (size_t x = 0; x < w; ++x) {
      if (isEdge[y * w + x]) last = static_cast<int>(x);
      if (static_cast<int>(x) - last <= r) g[y * w + x] = static_cast<int>(x) - last;
    }
    last = kFar;  // right to left
    for (size_t x = w; x-- > 0;) {
      if (isEdge[y * w + x]) last = static_cast<int>(x);
      if (last - static_cast<int>(x) <= r)
        g[y * w + x] = std::min(g[y * w + x], last - static_cast<int>(x));
    }
  }
  std::vector<float> distance(w * h, static_cast<float>(kMaxEdgeWidth));
  for (size_t y = 0; y < h; ++y)
    for (size_t x = 0; x < w; ++x) {
      float& at = distance[y * w + x];
      for (int oy = -r; oy <= r; ++oy) {
        const long py = static_cast<long>(y) + oy;
        if (py < 0 || py >= height) continue;
        const int gx = g[static_cast<size_t>(py) * w + x];
        if (gx == kFar) continue;
        at = std::min(at, static_cast<float>(std::sqrt(double(gx * gx + oy * oy))));
      }
    }
  return distance;
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
  fallbackFill += o.fallbackFill;
  return *this;
}

namespace {

// A camera's texture sample at a surface point.
struct Sample {
  bool inImage = false;            // some texel of the footprint is inside the image and the mask
  bool seen = false;               // ... and passes the depth test
  std::array<double, 3> colour{};  // over the texels that pass the depth test
  std::array<double, 3> colourIgnoringDepth{};  // over the in-mask texels (fallback)
  double edgeDistance = 0;  // over the texels that pass the depth test, as the colour
  double depth = 0;         // z of the point in the camera
};

Sample sampleCamera(const FrameViews& v, size_t i, const Vec3d& point, double tolerance) {
  Sample s;
  const Camera& c = v.cameras[i];
  const Vec3d q = c.toCamera(point);
  if (!(q[2] > 0)) return s;
  s.depth = q[2];
  const Vec2d p = c.projectCameraPoint(q);
  if (!(p[0] > -1 && p[0] < c.width && p[1] > -1 && p[1] < c.height)) return s;
  const int x0 = static_cast<int>(std::floor(p[0])), y0 = static_cast<int>(std::floor(p[1]));
  const double ax = p[0] - x0, ay = p[1] - y0;
  const Image& image = v.images[i];
  const Image& mask = v.masks[i];
  const std::vector<float>& depth = v.depth[i];
  const std::vector<float>& edge = v.edgeDistance[i];
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
    const size_t pixel =
        static_cast<size_t>(y) * static_cast<size_t>(c.width) + static_cast<size_t>(x);
    if (depth[pixel] < limit) continue;
    seenWeight += b;
    s.edgeDistance += b * edge[pixel];
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
    s.edgeDistance /= seenWeight;
  }
  return s;
}

uint8_t toByte(double v) {
  return static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

// Fallback `fill`: the pixels marked kSourceFill get a colour from the blended pixels around
// them by push-pull. Level 0 holds the blended pixels (weight 1) and the rest (weight 0); each
// coarser level holds, per 2 × 2 block of the finer one, the mean colour of its pixels of
// weight 1, with weight 1 when there is one. Going back down, every pixel of weight 0 takes the
// bilinear interpolation of the coarser level (pixel centres at 2X + 0.5, clamped at the
// borders) over its pixels of weight 1. A hole thus takes a smooth blend of the nearest blended
// pixels at the scale of the hole. Without any blended pixel, the flat colour.
void fillFromBlended(Image& out, const Image& source, const std::array<uint8_t, 3>& flat) {
  struct Level {
    int width = 0, height = 0;
    std::vector<std::array<double, 4>> px;  // r, g, b, weight (0 or 1)
    std::array<double, 4>& at(int x, int y) {
      return px[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
    }
  };
  std::vector<Level> levels(1);
  levels[0].width = out.width;
  levels[0].height = out.height;
  levels[0].px.assign(static_cast<size_t>(out.width) * static_cast<size_t>(out.height), {});
  bool any = false;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      if (source.at(x, y) == kSourceBlended) {
        auto& p = levels[0].at(x, y);
        for (int ch = 0; ch < 3; ++ch)
          p[static_cast<size_t>(ch)] = out.at(x, y, ch);
        p[3] = 1;
        any = true;
      }
  if (!any) {
    for (int y = 0; y < out.height; ++y)
      for (int x = 0; x < out.width; ++x)
        if (source.at(x, y) == kSourceFill)
          for (int ch = 0; ch < 3; ++ch)
            out.at(x, y, ch) = flat[static_cast<size_t>(ch)];
    return;
  }
  while (levels.back().width > 1 || levels.back().height > 1) {
    Level c;
    c.width = (levels.back().width + 1) / 2;
    c.height = (levels.back().height + 1) / 2;
    c.px.assign(static_cast<size_t>(c.width) * static_cast<size_t>(c.height), {});
    Level& f = levels.back();
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        const auto& p = f.at(x, y);
        auto& q = c.at(x / 2, y / 2);
        for (size_t k = 0; k < 4; ++k)
          q[k] += p[k];
      }
    for (auto& q : c.px)
      if (q[3] > 0) q = {q[0] / q[3], q[1] / q[3], q[2] / q[3], 1};
    levels.push_back(std::move(c));
  }
  for (size_t l = levels.size() - 1; l-- > 0;) {
    Level& f = levels[l];
    Level& c = levels[l + 1];
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        auto& p = f.at(x, y);
        if (p[3] > 0) continue;
        const double cx = std::clamp((x - 0.5) / 2, 0.0, c.width - 1.0);
        const double cy = std::clamp((y - 0.5) / 2, 0.0, c.height - 1.0);
        const int x0 = static_cast<int>(cx), y0 = static_cast<int>(cy);
        const int x1 = std::min(x0 + 1, c.width - 1), y1 = std::min(y0 + 1, c.height - 1);
        const double ax = cx - x0, ay = cy - y0;
        std::array<double, 4> sum{};
        const double b[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
        const std::array<double, 4>* q[4] = {&c.at(x0, y0), &c.at(x1, y0), &c.at(x0, y1),
                                             &c.at(x1, y1)};
        for (int k = 0; k < 4; ++k)
          for (size_t ch = 0; ch < 4; ++ch)
            sum[ch] += b[k] * (*q[k])[3] * (*q[k])[ch];
        if (sum[3] > 0) p = {sum[0] / sum[3], sum[1] / sum[3], sum[2] / sum[3], 1};
      }
  }
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      if (source.at(x, y) == kSourceFill) {
        const auto& p = levels[0].at(x, y);
        for (int ch = 0; ch < 3; ++ch)
          out.at(x, y, ch) = toByte(p[static_cast<size_t>(ch)]);
      }
}

}  // namespace

Image renderView(const FrameViews& v, const Camera& view, const RenderOptions& o,
                 const std::vector<bool>& useCamera, RenderStats* stats, Image* sources) {
  const size_t n = v.cameras.size();
  check(useCamera.empty() || useCamera.size() == n, "renderer: camera selection size mismatch");
  check(o.sharpness > 0, "renderer: the sharpness must be positive");
  check(o.depthTolerance >= 0, "renderer: the depth tolerance must not be negative");
  check(o.resolutionPenalty >= 0, "renderer: the resolution penalty must not be negative");
  check(o.edgeWidth >= 0 && o.edgeWidth <= kMaxEdgeWidth,
        "renderer: the edge width must be in 0 .. " + std::to_string(kMaxEdgeWidth));
  check(v.edgeDistance.size() == n, "renderer: the views have no edge maps (makeFrameViews)");
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
    std::vector<double> s(n), w(n), r(n), e(n);  // per camera that sees the point
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
        const double viewFootprint = view.toCamera(point)[2] / view.fx;
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
            r[seen] = samples[i].depth / v.cameras[i].fx / viewFootprint;
            e[seen] = o.edgeWidth > 0 ? samples[i].edgeDistance / o.edgeWidth : 1.0;
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
          if (o.blending == Blending::ulr)
            ulrWeights(s.data(), r.data(), e.data(), seen, o.sharpness, o.resolutionPenalty,
                       w.data());
          else
            viewWeights(s.data(), seen, o.sharpness, w.data());
          for (size_t j = 0; j < seen; ++j)
            for (size_t ch = 0; ch < 3; ++ch)
              colour[ch] += w[j] * seenColour[j][ch];
        } else if (o.fallback == Fallback::nearest && nearest < n) {
          ++st.fallbackNearest;
          source.at(x, y) = kSourceNearest;
          colour = samples[nearest].colourIgnoringDepth;
        } else if (o.fallback == Fallback::fill) {
          ++st.fallbackFill;
          source.at(x, y) = kSourceFill;  // coloured by fillFromBlended below
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
  if (o.fallback == Fallback::fill) fillFromBlended(out, source, o.fallbackColour);
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
  checkMaskedComparison(test, reference, mask, "PSNR");
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
