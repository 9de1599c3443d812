#include "tools/eval/view_weights.h"

#include <algorithm>
#include <cmath>

namespace tdvo {

double oneMinusCosine(const Vec3d& a, const Vec3d& b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return 0.5 * (dx * dx + dy * dy + dz * dz);
}

void viewWeights(const double* s, size_t count, double sharpness, double* w) {
  if (count == 0) return;
  double smallest = s[0];
  for (size_t i = 1; i < count; ++i)
    smallest = std::min(smallest, s[i]);
  double sum = 0;
  if (smallest <= 0) {
    // The view coincides with one or more cameras: they share the weight, the rest get none.
    for (size_t i = 0; i < count; ++i) {
      w[i] = s[i] <= 0 ? 1.0 : 0.0;
      sum += w[i];
    }
  } else {
    const double exponent = 0.5 * sharpness;
    for (size_t i = 0; i < count; ++i) {
      w[i] = std::pow(smallest / s[i], exponent);  // in [0, 1], 1 for the nearest camera
      sum += w[i];
    }
  }
  for (size_t i = 0; i < count; ++i)
    w[i] /= sum;  // sum ≥ 1: the nearest camera contributes 1
}

void ulrWeights(const double* s, const double* r, const double* e, size_t count, double sharpness,
                double beta, double* w) {
  if (count == 0) return;
  // The penalised s' in w: viewWeights reads s_i before it writes w_i, so it may work in place.
  for (size_t i = 0; i < count; ++i)
    w[i] = s[i] * (1 + beta * std::max(0.0, r[i] - 1));
  viewWeights(w, count, sharpness, w);
  double sum = 0;
  for (size_t i = 0; i < count; ++i) {
    w[i] *= std::clamp(e[i], kEdgeFloor, 1.0);
    sum += w[i];
  }
  for (size_t i = 0; i < count; ++i)
    w[i] /= sum;
}

}  // namespace tdvo
