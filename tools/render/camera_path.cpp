#include "tools/render/camera_path.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <utility>

#include "common/core/error.h"
#include "common/core/file_io.h"

namespace tdvo {

namespace {
constexpr double kPi = 3.14159265358979323846;

// The basis of azimuths about `up` through `centre`: a is camera 0's direction from the centre
// projected onto the plane normal to up (any direction in that plane when camera 0 is on the
// axis), b = up × a; azimuth θ is the direction cos θ · a + sin θ · b.
std::pair<Vec3d, Vec3d> azimuthBasis(const Dataset& d, const Vec3d& centre, const Vec3d& up) {
  check(!d.cameras.empty(), "the dataset has no cameras");
  const Vec3d r0 = d.cameras.front().camera.centre() - centre;
  Vec3d a = r0 - dot(r0, up) * up;
  if (norm(a) < 1e-9 * std::max(1.0, norm(r0))) {
    const Vec3d helper = std::fabs(up[2]) < 0.9 ? Vec3d{0, 0, 1} : Vec3d{1, 0, 0};
    a = cross(helper, up);
  }
  a = normalized(a);
  return {a, cross(up, a)};
}

}  // namespace

Camera virtualIntrinsics(const Dataset& d, int width, int height, double fieldOfView) {
  check(!d.cameras.empty(), "the dataset has no cameras");
  const Camera& first = d.cameras.front().camera;
  Camera c;
  c.name = "virtual";
  if (width == 0 && height == 0 && fieldOfView == 0) {
    c.width = first.width, c.height = first.height;
    c.fx = first.fx, c.fy = first.fy, c.cx = first.cx, c.cy = first.cy;
    return c;
  }
  c.width = width > 0 ? width : first.width;
  c.height = height > 0 ? height : first.height;
  c.fx = fieldOfView > 0 ? 0.5 * c.width / std::tan(0.5 * fieldOfView * kPi / 180)
                         : first.fx * c.width / first.width;
  c.fy = c.fx;
  c.cx = 0.5 * (c.width - 1);
  c.cy = 0.5 * (c.height - 1);
  return c;
}

Vec3d datasetUp(const Dataset& d) {
  if (d.up) return normalized(*d.up);
  Vec3d sum{0, 0, 0};
  for (const DatasetCamera& c : d.cameras)
    sum = sum + (-1.0) * c.camera.R[1];  // −y of the camera in the world: row 1 of R, negated
  check(norm(sum) > 1e-9, "the dataset has no up direction and its cameras' up directions cancel");
  return normalized(sum);
}

Vec3d boundingBoxCentre(const Mesh& mesh) {
  check(!mesh.positions.empty(), "the mesh has no vertices");
  const double inf = std::numeric_limits<double>::infinity();
  Vec3d lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  for (const Vec3d& p : mesh.positions)
    for (size_t i = 0; i < 3; ++i)
      lo[i] = std::min(lo[i], p[i]), hi[i] = std::max(hi[i], p[i]);
  return 0.5 * (lo + hi);
}

CameraArc cameraArc(const Dataset& d, const Vec3d& centre, const Vec3d& up) {
  const auto [a, b] = azimuthBasis(d, centre, up);
  std::vector<double> azimuths;
  for (const DatasetCamera& c : d.cameras) {
    const Vec3d r = c.camera.centre() - centre;
    const double azimuth = std::atan2(dot(r, b), dot(r, a));
    azimuths.push_back(azimuth < 0 ? azimuth + 2 * kPi : azimuth);
  }
  std::sort(azimuths.begin(), azimuths.end());
  CameraArc arc;
  arc.widestGap = -1;
  for (size_t i = 0; i < azimuths.size(); ++i) {
    const bool last = i + 1 == azimuths.size();
    const double gap = (last ? azimuths[0] + 2 * kPi : azimuths[i + 1]) - azimuths[i];
    if (gap > arc.widestGap) {
      arc.widestGap = gap;
      arc.start = azimuths[last ? 0 : i + 1];
    }
  }
  arc.span = 2 * kPi - arc.widestGap;
  const double meanSpacing = 2 * kPi / static_cast<double>(azimuths.size());
  arc.surrounds = arc.widestGap < std::min(1.5 * meanSpacing, 100 * kPi / 180);
  return arc;
}

std::vector<Camera> orbitPath(const Dataset& d, const Vec3d& centre, const Vec3d& up,
                              const Camera& intrinsics, const OrbitParams& p) {
  check(p.steps >= 1, "orbit: at least one step is needed");
  check(!d.cameras.empty(), "the dataset has no cameras");
  // Step k's azimuth: first + extent · k / divisions (a full turn: as many divisions as steps).
  double first = 0, extent = 2 * kPi * p.turns.value_or(1), divisions = p.steps;
  if (!p.turns) {
    const CameraArc arc = cameraArc(d, centre, up);
    if (!arc.surrounds) {  // from one end of the arc to the other
      first = p.steps == 1 ? arc.start + 0.5 * arc.span : arc.start;
      extent = arc.span;
      divisions = std::max(1, p.steps - 1);
    }
  }
  double distance = 0, elevation = 0;
  for (const DatasetCamera& c : d.cameras) {
    const Vec3d r = c.camera.centre() - centre;
    distance += norm(r);
    elevation += std::asin(std::clamp(dot(normalized(r), up), -1.0, 1.0));
  }
  distance /= static_cast<double>(d.cameras.size());
  elevation /= static_cast<double>(d.cameras.size());
  if (p.distance > 0) distance = p.distance;
  if (p.elevation) elevation = *p.elevation * kPi / 180;
  const auto [a, b] = azimuthBasis(d, centre, up);
  // Keep the cameras off the up axis, where lookAt has no defined image-up.
  elevation = std::clamp(elevation, -89.9 * kPi / 180, 89.9 * kPi / 180);
  std::vector<Camera> path;
  for (int k = 0; k < p.steps; ++k) {
    const double azimuth = first + extent * k / divisions;
    const Vec3d direction = std::cos(elevation) * (std::cos(azimuth) * a + std::sin(azimuth) * b) +
                            std::sin(elevation) * up;
    Camera c = intrinsics;
    char name[32];
    std::snprintf(name, sizeof name, "orbit%04d", k);
    c.name = name;
    lookAt(c, centre + distance * direction, centre, up);
    path.push_back(c);
  }
  return path;
}

std::vector<Camera> readPoses(const std::string& path, const Camera& intrinsics, const Vec3d& up) {
  std::vector<Camera> poses;
  if (path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0) {
    const Dataset d = readDataset(path);
    for (const DatasetCamera& c : d.cameras) {
      // Its image size is the rendered view's: the limit of --Width and --Height applies (a
      // dataset's own cameras have their images, which bound their size; these have none).
      check(c.camera.width <= kMaxViewSize && c.camera.height <= kMaxViewSize,
            path + ": camera '" + c.camera.name + "': image size " +
                std::to_string(c.camera.width) + " x " + std::to_string(c.camera.height) +
                " is larger than a rendered view may be (" + std::to_string(kMaxViewSize) + " x " +
                std::to_string(kMaxViewSize) + ")");
      poses.push_back(c.camera);
    }
    return poses;
  }
  std::istringstream in(readTextFile(path, kMaxTextFileBytes, "a camera path"));
  std::string line;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    const std::string where = path + ":" + std::to_string(lineNumber) + ": ";
    line = line.substr(0, line.find('#'));
    std::istringstream fields(line);
    std::vector<double> v;
    std::string token;
    while (fields >> token) {
      char* end = nullptr;
      const double x = std::strtod(token.c_str(), &end);
      check(end && *end == 0 && std::isfinite(x), where + "'" + token + "' is not a number");
      v.push_back(x);
    }
    if (v.empty()) continue;
    check(v.size() == 6 || v.size() == 9,
          where + "expected 6 numbers (eye, target) or 9 (eye, target, up), found " +
              std::to_string(v.size()));
    const Vec3d eye{v[0], v[1], v[2]}, target{v[3], v[4], v[5]};
    const Vec3d poseUp = v.size() == 9 ? Vec3d{v[6], v[7], v[8]} : up;
    const Vec3d forward = target - eye;
    check(norm(forward) > 0, where + "eye and target are the same point");
    check(norm(poseUp) > 0 && norm(cross(forward, poseUp)) > 1e-9 * norm(forward) * norm(poseUp),
          where + "the up direction is zero or parallel to the viewing direction");
    Camera c = intrinsics;
    char name[32];
    std::snprintf(name, sizeof name, "pose%04d", static_cast<int>(poses.size()));
    c.name = name;
    lookAt(c, eye, target, poseUp);
    poses.push_back(c);
  }
  check(!poses.empty(), path + ": no poses");
  return poses;
}

}  // namespace tdvo
