// The view-dependent texture weights (tools/eval/view_weights.h): they sum to 1, belong exactly to
// one camera at its own pose, and are continuous in between cameras.
#include "tools/eval/view_weights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "common/views/camera.h"

using namespace tdvo;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Unit direction at azimuth `a` and elevation `e` (radians).
Vec3d direction(double a, double e) {
  return {std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a)};
}

// A ring of `n` camera directions plus two off the ring (like a dome's top).
std::vector<Vec3d> rigDirections(int n) {
  std::vector<Vec3d> d;
  for (int i = 0; i < n; ++i)
    d.push_back(direction(2 * kPi * i / n, 0.2));
  d.push_back(direction(0.3, 1.2));
  d.push_back(direction(2.5, -0.9));
  return d;
}

std::vector<double> weightsFor(const std::vector<Vec3d>& cameras, const Vec3d& view, double k) {
  std::vector<double> s, w(cameras.size());
  for (const Vec3d& c : cameras)
    s.push_back(oneMinusCosine(c, view));
  viewWeights(s.data(), s.size(), k, w.data());
  return w;
}

double maxDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i)
    m = std::max(m, std::fabs(a[i] - b[i]));
  return m;
}

}  // namespace

TEST(ViewWeights, OneMinusCosineIsExactAtZeroAndAccurateForSmallAngles) {
  const Vec3d a = normalized({0.3, -0.4, 0.86});
  EXPECT_EQ(oneMinusCosine(a, a), 0.0);
  EXPECT_NEAR(oneMinusCosine({1, 0, 0}, {0, 1, 0}), 1.0, 1e-15);
  EXPECT_NEAR(oneMinusCosine({1, 0, 0}, {-1, 0, 0}), 2.0, 1e-15);
  // For a small angle θ, 1 − cos θ = 2 sin²(θ/2) with full relative precision.
  for (double theta : {1e-3, 1e-6, 1e-9, 1e-12}) {
    const double expected = 2 * std::sin(theta / 2) * std::sin(theta / 2);
    EXPECT_NEAR(oneMinusCosine({1, 0, 0}, {std::cos(theta), std::sin(theta), 0}) / expected, 1.0,
                1e-6)
        << "theta " << theta;
  }
}

TEST(ViewWeights, SumToOneAndAreNonNegative) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> angle(-kPi, kPi), height(-1.5, 1.5);
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = 1 + trial % 17;
    std::vector<Vec3d> cameras;
    for (int i = 0; i < n; ++i)
      cameras.push_back(direction(angle(random), height(random)));
    const Vec3d view = direction(angle(random), height(random));
    for (double k : {0.5, 1.0, 4.0, 8.0, 64.0, 1000.0}) {
      const std::vector<double> w = weightsFor(cameras, view, k);
      double sum = 0;
      for (double x : w) {
        ASSERT_TRUE(std::isfinite(x));
        ASSERT_GE(x, 0.0);
        sum += x;
      }
      ASSERT_NEAR(sum, 1.0, 1e-12) << "trial " << trial << " k " << k;
    }
  }
}

TEST(ViewWeights, RatiosFollowTheFormula) {
  // w_i / w_j = ((1 − cos θ_j) / (1 − cos θ_i))^(k/2).
  const std::vector<double> s = {0.1, 0.4, 1.3, 2.0};
  std::vector<double> w(s.size());
  const double k = 3;
  viewWeights(s.data(), s.size(), k, w.data());
  for (size_t i = 0; i < s.size(); ++i)
    for (size_t j = 0; j < s.size(); ++j)
      EXPECT_NEAR(w[i] / w[j], std::pow(s[j] / s[i], k / 2), 1e-12);
}

TEST(ViewWeights, ExactlyOneCameraAtItsOwnPose) {
  const std::vector<Vec3d> cameras = rigDirections(8);
  for (size_t j = 0; j < cameras.size(); ++j)
    for (double k : {0.5, 4.0, 8.0, 100.0}) {
      const std::vector<double> w = weightsFor(cameras, cameras[j], k);
      for (size_t i = 0; i < cameras.size(); ++i)
        EXPECT_EQ(w[i], i == j ? 1.0 : 0.0) << "camera " << j << " weight " << i << " k " << k;
    }
  // With real cameras: a virtual camera that is a copy of camera 3 has exactly its direction,
  // both for the optical axes and for the rays from a surface point to the centres.
  std::vector<Camera> rig(6);
  for (size_t i = 0; i < rig.size(); ++i)
    lookAt(rig[i], 4.0 * direction(2 * kPi * double(i) / 6, 0.3), {0, 0, 0}, {0, 1, 0});
  const Camera view = rig[3];
  const Vec3d point = {0.2, -0.1, 0.3};
  std::vector<double> sAxis, sRay;
  for (const Camera& c : rig) {
    sAxis.push_back(oneMinusCosine(c.viewingDirection(), view.viewingDirection()));
    sRay.push_back(
        oneMinusCosine(normalized(c.centre() - point), normalized(view.centre() - point)));
  }
  for (const std::vector<double>* s : {&sAxis, &sRay}) {
    std::vector<double> w(rig.size());
    viewWeights(s->data(), s->size(), 8, w.data());
    for (size_t i = 0; i < rig.size(); ++i)
      EXPECT_EQ(w[i], i == 3 ? 1.0 : 0.0);
  }
}

TEST(ViewWeights, CoincidentCamerasShareEqually) {
  const std::vector<double> s = {0.5, 0.0, 0.2, 0.0};
  std::vector<double> w(s.size());
  viewWeights(s.data(), s.size(), 8, w.data());
  EXPECT_EQ(w, (std::vector<double>{0.0, 0.5, 0.0, 0.5}));
}

TEST(ViewWeights, ContinuousBetweenAndThroughCameras) {
  // The view sweeps a full circle around the ring (through every camera direction and between
  // them) and a path over the top: the weights change by at most a small amount per small
  // step, and by proportionally less for a ten times smaller step (no jumps anywhere,
  // including at the cameras' own directions, where the weights become one camera's).
  const std::vector<Vec3d> cameras = rigDirections(8);
  for (double k : {1.0, 8.0, 32.0}) {
    for (int path = 0; path < 2; ++path) {
      auto at = [&](double t) { return path == 0 ? direction(t, 0.2) : direction(0.3, t); };
      const double step = 1e-3;
      double worst = 0, worstFine = 0;
      std::vector<double> previous = weightsFor(cameras, at(0), k);
      for (double t = step; t <= 2 * kPi; t += step) {
        const std::vector<double> w = weightsFor(cameras, at(t), k);
        worst = std::max(worst, maxDifference(w, previous));
        worstFine =
            std::max(worstFine, maxDifference(weightsFor(cameras, at(t + step / 10), k), w));
        previous = w;
      }
      EXPECT_LT(worst, 0.02 * std::max(1.0, k / 4)) << "k " << k << " path " << path;
      EXPECT_LT(worstFine, 0.25 * worst + 1e-9) << "k " << k << " path " << path;
    }
  }
}

TEST(ViewWeights, ApproachTheOwnCameraLimitWithoutOverflow) {
  // As the view approaches camera j the weights tend to the delta at j, with no overflow even
  // for tiny angles and a large sharpness.
  const std::vector<Vec3d> cameras = rigDirections(8);
  for (double k : {2.0, 8.0, 1000.0}) {
    double previousOwn = 0;
    for (double theta : {1e-1, 1e-2, 1e-4, 1e-8, 1e-12, 1e-100}) {
      const std::vector<double> w = weightsFor(cameras, direction(2 * kPi * 2 / 8 + theta, 0.2), k);
      for (double x : w)
        ASSERT_TRUE(std::isfinite(x));
      EXPECT_GE(w[2], previousOwn) << "k " << k << " theta " << theta;
      previousOwn = w[2];
    }
    EXPECT_GT(previousOwn, 1 - 1e-12) << "k " << k;
  }
}

TEST(ViewWeights, NoCameras) {
  viewWeights(nullptr, 0, 8, nullptr);  // nothing to do, nothing touched
}

TEST(UlrWeights, SumToOneAndAreNonNegativeForAnyResolutionAndEdge) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    const size_t n = 1 + trial % 17;
    std::vector<double> s(n), r(n), e(n), w(n);
    for (size_t i = 0; i < n; ++i) {
      s[i] = 2 * unit(rng);
      r[i] = 4 * unit(rng);
      e[i] = trial % 3 == 0 ? 0.0 : unit(rng);  // every edge factor 0 in a third of the rigs
    }
    ulrWeights(s.data(), r.data(), e.data(), n, 1 + trial % 6, unit(rng) * 3, w.data());
    double sum = 0;
    for (double x : w) {
      EXPECT_GE(x, 0.0);
      sum += x;
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
  }
}

TEST(UlrWeights, ExactlyOneCameraAtItsOwnPoseWhateverResolutionAndEdge) {
  // s_j = 0: camera j's weight is exactly 1 even on its own edge (e = 0) and with coarse texels.
  const std::vector<double> s = {0.3, 0.0, 0.01, 1.5}, r = {1, 3, 0.5, 1}, e = {1, 0, 1, 1};
  std::vector<double> w(4);
  ulrWeights(s.data(), r.data(), e.data(), 4, 4, 2, w.data());
  EXPECT_EQ(w[1], 1.0);
  EXPECT_EQ(w[0], 0.0);
  EXPECT_EQ(w[2], 0.0);
  EXPECT_EQ(w[3], 0.0);
}

TEST(UlrWeights, EdgeAndResolutionMoveWeightAwayAndAreContinuous) {
  const std::vector<double> s = {0.1, 0.1}, r = {1, 1};
  std::vector<double> w(2), previous(2);
  // Equal cameras share; as camera 0 nears its edge (e → 0) its weight falls smoothly to the
  // floor's share, and never jumps.
  std::vector<double> e = {1, 1};
  ulrWeights(s.data(), r.data(), e.data(), 2, 4, 1, previous.data());
  EXPECT_NEAR(previous[0], 0.5, 1e-15);
  for (double e0 = 1; e0 >= 0; e0 -= 1e-3) {
    e[0] = std::max(e0, 0.0);
    ulrWeights(s.data(), r.data(), e.data(), 2, 4, 1, w.data());
    EXPECT_LE(w[0], previous[0] + 1e-15);
    EXPECT_LT(maxDifference(w, previous), 2e-3);
    previous = w;
  }
  EXPECT_NEAR(w[0], kEdgeFloor / (1 + kEdgeFloor), 1e-12);
  // Coarser texels (r > 1) lower a camera's weight; finer ones (r < 1) change nothing.
  const std::vector<double> coarse = {2, 1}, fine = {0.5, 1}, full = {1, 1};
  ulrWeights(s.data(), coarse.data(), full.data(), 2, 4, 1, w.data());
  EXPECT_NEAR(w[0], 1 / (1 + std::pow(2.0, 2)), 1e-12);  // s'_0 = 2 s_0: (1/2)^(k/2) = 1/4
  ulrWeights(s.data(), fine.data(), full.data(), 2, 4, 1, w.data());
  EXPECT_NEAR(w[0], 0.5, 1e-15);
}
