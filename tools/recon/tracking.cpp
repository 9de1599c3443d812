#include "tools/recon/tracking.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "common/core/error.h"
#include "common/views/camera.h"
#include "tools/eval/metrics.h"
#include "tools/recon/closest_point.h"

namespace tdvo {

namespace {

// A closest point that counts: one was found (a facing triangle; none leaves the triangle
// UINT32_MAX) within the distance limit. Written so that a NaN distance, or an infinite limit
// on a mesh whose size overflowed, never counts a point that does not exist.
bool found(const ClosestPoint& c, double maxSquared) {
  return c.triangle != UINT32_MAX && c.squaredDistance <= maxSquared;
}

// Area-weighted vertex normals (unit; zero for isolated vertices) and unit face normals.
void computeNormals(const Mesh& mesh, std::vector<Vec3d>& vertexNormals,
                    std::vector<Vec3d>& faceNormals) {
  vertexNormals.assign(mesh.positions.size(), {0, 0, 0});
  faceNormals.resize(mesh.triangles.size());
  for (size_t f = 0; f < mesh.triangles.size(); ++f) {
    const Triangle& t = mesh.triangles[f];
    const Vec3d n = cross(mesh.positions[t[1]] - mesh.positions[t[0]],
                          mesh.positions[t[2]] - mesh.positions[t[0]]);
    for (uint32_t v : t)
      vertexNormals[v] = vertexNormals[v] + n;
    const double len = norm(n);
    faceNormals[f] = len > 0 ? (1 / len) * n : Vec3d{0, 0, 0};
  }
  for (Vec3d& n : vertexNormals) {
    const double len = norm(n);
    if (len > 0) n = (1 / len) * n;
  }
}

// Rigid ICP: moves the whole pose by the rotation and translation that best bring a sample of
// its vertices onto the tangent planes of their closest facing points of the target
// (point-to-plane, linearised rotation: a 6 × 6 least-squares system per iteration, Chen &
// Medioni 1992), repeated `iterations` times. Takes out the global motion before the non-rigid
// fit, which would otherwise have to drag every vertex tangentially through point pulls.
void alignRigidly(Mesh& pose, const TriangleBvh& target, int iterations, double maxSquared,
                  double minCos) {
  const size_t n = pose.positions.size();
  const size_t step = std::max<size_t>(1, n / 2000);
  std::vector<uint32_t> hint(n, UINT32_MAX);
  for (int iteration = 0; iteration < iterations; ++iteration) {
    std::vector<Vec3d> normals, faceNormals;
    computeNormals(pose, normals, faceNormals);
    // Residual of sample i after the motion (ω, t): (p − q)·m + ω·(p × m) + t·m.
    Eigen::Matrix<double, 6, 6> ata = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> atb = Eigen::Matrix<double, 6, 1>::Zero();
    size_t pairs = 0;
    for (size_t i = 0; i < n; i += step) {
      const Vec3d& p = pose.positions[i];
      const ClosestPoint c = target.closestFacing(p, normals[i], minCos, hint[i]);
      if (!found(c, maxSquared)) continue;
      hint[i] = c.triangle;
      const Vec3d& m = target.normal(c.triangle);
      const Vec3d pm = cross(p, m);
      Eigen::Matrix<double, 6, 1> row;
      row << pm[0], pm[1], pm[2], m[0], m[1], m[2];
      ata += row * row.transpose();
      atb -= row * dot(p - c.point, m);
      ++pairs;
    }
    if (pairs < 6) return;
    // A little damping keeps the system solvable for shapes that slide along themselves.
    ata += 1e-9 * ata.trace() * Eigen::Matrix<double, 6, 6>::Identity();
    const Eigen::Matrix<double, 6, 1> x = ata.ldlt().solve(atb);
    if (!x.allFinite()) return;
    const Vec3d omega = {x[0], x[1], x[2]};
    const Mat3d r = rotationFromRodrigues(omega);
    const Vec3d t = {x[3], x[4], x[5]};
    for (Vec3d& p : pose.positions)
      p = r * p + t;
    if (norm(omega) < 1e-9 && norm(t) < 1e-9 * std::sqrt(maxSquared)) return;
  }
}

}  // namespace

struct MeshTracker::State {
  TrackingOptions options;
  Mesh rest, pose;
  std::vector<std::pair<uint32_t, uint32_t>> edges;  // unique, i < j
  double diagonal = 1;
};

MeshTracker::MeshTracker(const Mesh& rest, const TrackingOptions& options)
    : state_(std::make_unique<State>()) {
  check(!rest.triangles.empty(), "tracking: the GOM's first mesh has no triangles");
  state_->options = options;
  state_->rest = rest;
  state_->pose = rest;
  for (const Triangle& t : rest.triangles)
    for (size_t k = 0; k < 3; ++k) {
      const uint32_t a = t[k], b = t[(k + 1) % 3];
      state_->edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(state_->edges.begin(), state_->edges.end());
  state_->edges.erase(std::unique(state_->edges.begin(), state_->edges.end()), state_->edges.end());
  BoundingBox box;
  box.extend(rest.positions);
  state_->diagonal = std::max(box.diagonal(), 1e-300);
}

MeshTracker::~MeshTracker() = default;
MeshTracker::MeshTracker(MeshTracker&&) noexcept = default;
MeshTracker& MeshTracker::operator=(MeshTracker&&) noexcept = default;

const Mesh& MeshTracker::current() const {
  return state_->pose;
}

FitStats MeshTracker::fit(const Mesh& target) {
  check(!target.triangles.empty(), "tracking: the target mesh has no triangles");
  const auto start = std::chrono::steady_clock::now();
  State& s = *state_;
  const TrackingOptions& o = s.options;
  const size_t n = s.pose.positions.size();
  const double maxSquared = std::pow(o.maxDistance * s.diagonal, 2);
  const double minCos = std::cos(o.maxAngle * M_PI / 180);

  const TriangleBvh targetBvh(target);
  std::vector<Vec3d> targetVertexNormals, targetFaceNormals;
  computeNormals(target, targetVertexNormals, targetFaceNormals);
  (void)targetFaceNormals;
  // Target samples: its vertices used by a triangle, thinned to at most twice the mesh's
  // vertex count.
  std::vector<uint32_t> samples;
  {
    std::vector<bool> used(target.positions.size(), false);
    for (const Triangle& t : target.triangles)
      for (uint32_t v : t)
        used[v] = true;
    size_t count = static_cast<size_t>(std::count(used.begin(), used.end(), true));
    const size_t step = std::max<size_t>(1, count / std::max<size_t>(1, 2 * n));
    size_t k = 0;
    for (uint32_t v = 0; v < used.size(); ++v)
      if (used[v] && k++ % step == 0) samples.push_back(v);
  }

  // Rest-pose edge vectors (fixed) and the uniform-weight Laplacian's diagonal.
  std::vector<double> degree(n, 0);
  for (const auto& [a, b] : s.edges) {
    degree[a] += 1;
    degree[b] += 1;
  }

  FitStats stats;
  std::vector<uint32_t> vertexHint(n, UINT32_MAX);
  alignRigidly(s.pose, targetBvh, o.rigidIterations, maxSquared, minCos);
  std::vector<Eigen::Matrix3d> rotation(n, Eigen::Matrix3d::Identity());
  TriangleBvh poseBvh;
  for (int iteration = 0; iteration < o.iterations; ++iteration) {
    const double t = o.iterations > 1 ? double(iteration) / (o.iterations - 1) : 1.0;
    const double stiffness = o.stiffness * std::pow(o.finalStiffness / o.stiffness, t);
    std::vector<Vec3d> vertexNormals, faceNormals;
    computeNormals(s.pose, vertexNormals, faceNormals);

    // Local step: rotations from the covariance of rest and current one-ring edges.
    std::vector<Eigen::Matrix3d> covariance(n, Eigen::Matrix3d::Zero());
    for (const auto& [a, b] : s.edges) {
      const Vec3d pr = s.rest.positions[a] - s.rest.positions[b];
      const Vec3d pc = s.pose.positions[a] - s.pose.positions[b];
      const Eigen::Vector3d er(pr[0], pr[1], pr[2]), ec(pc[0], pc[1], pc[2]);
      const Eigen::Matrix3d outer = er * ec.transpose();
      covariance[a] += outer;
      covariance[b] += outer;
    }
    for (size_t i = 0; i < n; ++i) {
      Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance[i],
                                            Eigen::ComputeFullU | Eigen::ComputeFullV);
      Eigen::Matrix3d u = svd.matrixU();
      Eigen::Matrix3d r = svd.matrixV() * u.transpose();
      if (r.determinant() < 0) {
        u.col(2) *= -1;
        r = svd.matrixV() * u.transpose();
      }
      rotation[i] = r;
    }

    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(n + 2 * s.edges.size() + 9 * samples.size());
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), 3);
    // ARAP term, plus a tiny pull to the current pose that keeps the system definite for parts
    // of the mesh no correspondence reaches.
    const double anchor = 1e-4;
    for (size_t i = 0; i < n; ++i) {
      triplets.emplace_back(i, i, stiffness * degree[i] + anchor);
      const Vec3d& p = s.pose.positions[i];
      rhs.row(static_cast<Eigen::Index>(i)) += anchor * Eigen::RowVector3d(p[0], p[1], p[2]);
    }
    for (const auto& [a, b] : s.edges) {
      triplets.emplace_back(a, b, -stiffness);
      triplets.emplace_back(b, a, -stiffness);
      const Vec3d pr = s.rest.positions[a] - s.rest.positions[b];
      const Eigen::Vector3d e =
          0.5 * stiffness * (rotation[a] + rotation[b]) * Eigen::Vector3d(pr[0], pr[1], pr[2]);
      rhs.row(a) += e.transpose();
      rhs.row(b) -= e.transpose();
    }
    // Vertex → target correspondences.
    stats.vertexPairs = 0;
    for (size_t i = 0; i < n; ++i) {
      const ClosestPoint c =
          targetBvh.closestFacing(s.pose.positions[i], vertexNormals[i], minCos, vertexHint[i]);
      if (!found(c, maxSquared)) continue;
      vertexHint[i] = c.triangle;
      ++stats.vertexPairs;
      triplets.emplace_back(i, i, 1.0);
      rhs.row(static_cast<Eigen::Index>(i)) +=
          Eigen::RowVector3d(c.point[0], c.point[1], c.point[2]);
    }
    // Target → mesh correspondences.
    if (poseBvh.triangleCount() == 0)
      poseBvh = TriangleBvh(s.pose);
    else
      poseBvh.refit(s.pose);
    const double sampleWeight = double(n) / double(std::max<size_t>(1, samples.size()));
    stats.targetPairs = 0;
    uint32_t hint = UINT32_MAX;
    for (uint32_t v : samples) {
      const Vec3d& q = target.positions[v];
      const ClosestPoint c = poseBvh.closestFacing(q, targetVertexNormals[v], minCos, hint);
      if (!found(c, maxSquared)) continue;
      hint = c.triangle;
      ++stats.targetPairs;
      const Triangle& tri = s.pose.triangles[c.triangle];
      for (size_t r = 0; r < 3; ++r) {
        for (size_t k = 0; k < 3; ++k)
          triplets.emplace_back(tri[r], tri[k], sampleWeight * c.barycentric[r] * c.barycentric[k]);
        rhs.row(tri[r]) += sampleWeight * c.barycentric[r] * Eigen::RowVector3d(q[0], q[1], q[2]);
      }
    }
    if (stats.vertexPairs + stats.targetPairs == 0) break;  // nothing to pull towards

    Eigen::SparseMatrix<double> a(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    a.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(a);
    if (solver.info() != Eigen::Success) break;
    const Eigen::MatrixXd x = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !x.allFinite()) break;
    for (size_t i = 0; i < n; ++i)
      s.pose.positions[i] = {x(static_cast<Eigen::Index>(i), 0), x(static_cast<Eigen::Index>(i), 1),
                             x(static_cast<Eigen::Index>(i), 2)};
  }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace tdvo
