#include "tools/recon/calibration_refinement.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/core/error.h"
#include "common/views/rasteriser.h"
#include "tools/recon/carving_view.h"
#include "tools/recon/silhouettes.h"

namespace tdvo {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The camera `input` moved by parameters x: x[0..2] a rotation (Rodrigues, radians) applied in
// the camera frame, x[3..5] a displacement of the centre (world), x[6] (if present) the log of
// the focal length factor.
Camera movedCamera(const Camera& input, const std::vector<double>& x) {
  Camera c = input;
  const Vec3d centre = input.centre();
  c.R = rotationFromRodrigues({x[0], x[1], x[2]}) * input.R;
  const Vec3d moved = centre + Vec3d{x[3], x[4], x[5]};
  const Vec3d rc = c.R * moved;
  c.t = {-rc[0], -rc[1], -rc[2]};
  if (x.size() > 6) {
    const double s = std::exp(x[6]);
    c.fx = input.fx * s;
    c.fy = input.fy * s;
  }
  return c;
}

Mesh hullSurface(const std::vector<Camera>& cameras, const std::vector<Image>& silhouettes,
                 const CaptureCube& cube, const HullOptions& options, size_t skip) {
  std::vector<CanvasMap> maps;
  std::vector<CarvingView> views;
  maps.reserve(cameras.size());
  views.reserve(cameras.size());
  for (size_t c = 0; c < cameras.size(); ++c) {
    if (c == skip) continue;
    maps.push_back(CanvasMap::build(cameras[c]));
    views.emplace_back(maps.back(), silhouettes[c]);
  }
  HullOptions o = options;
  o.minViews = std::clamp(o.minViews, 1, static_cast<int>(views.size()));
  return carveVisualHull(views, cube, o).surface;
}

double meanIoU(const Mesh& hull, const std::vector<Camera>& cameras,
               const std::vector<Image>& silhouettes) {
  double sum = 0;
  for (size_t c = 0; c < cameras.size(); ++c)
    sum += maskIoU(renderMask(hull, cameras[c]), silhouettes[c]);
  return sum / double(cameras.size());
}

}  // namespace

std::vector<double> nelderMead(const std::function<double(const std::vector<double>&)>& f,
                               const std::vector<double>& start, const std::vector<double>& steps,
                               int evaluations, double& best) {
  const size_t n = start.size();
  std::vector<std::vector<double>> p(n + 1, start);
  std::vector<double> v(n + 1);
  for (size_t k = 0; k < n; ++k)
    p[k + 1][k] += steps[k];
  int used = 0;
  for (size_t k = 0; k <= n; ++k, ++used)
    v[k] = f(p[k]);
  std::vector<size_t> order(n + 1);
  auto point = [&](const std::vector<double>& a, const std::vector<double>& b, double s) {
    std::vector<double> r(n);
    for (size_t k = 0; k < n; ++k)
      r[k] = a[k] + s * (b[k] - a[k]);
    return r;
  };
  while (used < evaluations) {
    for (size_t k = 0; k <= n; ++k)
      order[k] = k;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return v[a] < v[b]; });
    const size_t lo = order[0], hi = order[n], second = order[n - 1];
    std::vector<double> centroid(n, 0.0);
    for (size_t k = 0; k <= n; ++k)
      if (k != hi)
        for (size_t d = 0; d < n; ++d)
          centroid[d] += p[k][d] / double(n);
    const std::vector<double> reflected = point(centroid, p[hi], -1.0);
    const double fr = f(reflected);
    ++used;
    if (fr < v[lo]) {
      const std::vector<double> expanded = point(centroid, p[hi], -2.0);
      const double fe = f(expanded);
      ++used;
      if (fe < fr) {
        p[hi] = expanded;
        v[hi] = fe;
      } else {
        p[hi] = reflected;
        v[hi] = fr;
      }
    } else if (fr < v[second]) {
      p[hi] = reflected;
      v[hi] = fr;
    } else {
      const bool outside = fr < v[hi];
      const std::vector<double> contracted = point(centroid, outside ? reflected : p[hi], 0.5);
      const double fc = f(contracted);
      ++used;
      if (fc < (outside ? fr : v[hi])) {
        p[hi] = contracted;
        v[hi] = fc;
      } else {  // shrink towards the best point
        for (size_t k = 0; k <= n && used < evaluations; ++k)
          if (k != lo) {
            p[k] = point(p[lo], p[k], 0.5);
            v[k] = f(p[k]);
            ++used;
          }
      }
    }
  }
  const size_t bestIndex = static_cast<size_t>(std::min_element(v.begin(), v.end()) - v.begin());
  best = v[bestIndex];
  return p[bestIndex];
}

CalibrationRefinementResult refineCalibration(std::vector<Camera>& cameras,
                                              const std::vector<Image>& silhouettes,
                                              const CaptureCube& cube,
                                              const CalibrationRefinementOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  check(cameras.size() >= 2, "RefineCalibration needs at least two cameras");
  check(cameras.size() == silhouettes.size(), "refineCalibration: one silhouette per camera");
  CalibrationRefinementResult result;
  HullOptions hullOptions = options.hull;
  hullOptions.depth = options.depth;
  const std::vector<Camera> input = cameras;
  result.meanIouBefore = meanIoU(
      hullSurface(cameras, silhouettes, cube, hullOptions, cameras.size()), cameras, silhouettes);
  result.meanIouAfter = result.meanIouBefore;
  const Vec3d centre = cube.origin + Vec3d{cube.size / 2, cube.size / 2, cube.size / 2};
  const size_t n = options.focal ? 7 : 6;
  // Parameters of each camera relative to its input pose.
  std::vector<std::vector<double>> params(cameras.size(), std::vector<double>(n, 0.0));
  for (int round = 0; round < options.rounds; ++round) {
    const std::vector<Camera> before = cameras;
    const std::vector<std::vector<double>> paramsBefore = params;
    std::vector<CameraRefinement> reports(cameras.size());
    for (size_t c = 0; c < cameras.size(); ++c) {
      const Mesh hull = hullSurface(cameras, silhouettes, cube, hullOptions, c);
      CameraRefinement& r = reports[c];
      r.name = cameras[c].name;
      if (hull.triangles.empty()) {  // the others agree on nothing: leave this camera
        r.iouBefore = r.iouAfter = 0;
        continue;
      }
      const double distance = norm(input[c].centre() - centre);
      const double maxAngle = options.maxRotation * kPi / 180;
      const double maxMove = options.maxTranslation * distance;
      const double maxLogFocal = std::log1p(options.maxFocalChange);
      auto objective = [&](const std::vector<double>& x) {
        if (norm({x[0], x[1], x[2]}) > maxAngle || norm({x[3], x[4], x[5]}) > maxMove ||
            (n > 6 && std::fabs(x[6]) > maxLogFocal))
          return 2.0;
        return 1.0 - maskIoU(renderMask(hull, movedCamera(input[c], x)), silhouettes[c]);
      };
      r.iouBefore = 1.0 - objective(params[c]);
      const double angleStep = options.rotationStep * kPi / 180;
      const double moveStep = options.translationStep * distance;
      std::vector<double> steps = {angleStep, angleStep, angleStep, moveStep, moveStep, moveStep};
      if (n > 6) steps.push_back(0.005);
      double best = 0;
      const std::vector<double> x =
          nelderMead(objective, params[c], steps, options.evaluations, best);
      if (1.0 - best > r.iouBefore) {
        params[c] = x;
        cameras[c] = movedCamera(input[c], x);
      }
      r.iouAfter = 1.0 - objective(params[c]);
      r.rotationDegrees = norm({params[c][0], params[c][1], params[c][2]}) * 180 / kPi;
      r.translation = norm({params[c][3], params[c][4], params[c][5]});
      r.focalFactor = n > 6 ? std::exp(params[c][6]) : 1.0;
    }
    const double mean = meanIoU(
        hullSurface(cameras, silhouettes, cube, hullOptions, cameras.size()), cameras, silhouettes);
    if (mean <= result.meanIouAfter) {  // the pass did not help: undo it and stop
      cameras = before;
      params = paramsBefore;
      break;
    }
    result.meanIouAfter = mean;
    result.cameras = reports;
    ++result.passesKept;
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace tdvo
