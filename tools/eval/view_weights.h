// View-dependent texture weights: how much each camera's texture contributes when a 3D video
// object is watched from a virtual viewpoint (docs/rendering.md states the formula and its
// properties).
//
// For camera i let θ_i be the angle between the camera's direction d_i and the virtual view's
// direction v (both unit vectors; which directions is the caller's choice, see ViewDirection in
// tools/render/view_renderer.h: the optical axes, as in the source paper, or the directions from
// the surface point to the camera centres). The weights are
//
//   s_i = 1 − cos θ_i = |d_i − v|² / 2                 (0 when the directions coincide)
//   w_i = (s_min / s_i)^(k/2) / Σ_j (s_min / s_j)^(k/2),   s_min = min_j s_j
//
// i.e. w_i ∝ (1 − cos θ_i)^(−k/2) ∝ sin(θ_i / 2)^(−k), with the sharpness k > 0. Writing the
// ratio to the nearest camera keeps every term in [0, 1] (no overflow near θ = 0). When
// s_min = 0 (the view coincides with one or more cameras exactly) those cameras share the weight
// equally and every other camera gets 0. Properties (tested in tests/view_weights_test.cpp):
//   1. w_i ≥ 0 and Σ w_i = 1 for any non-empty set of cameras;
//   2. at a camera's own direction that camera's weight is exactly 1, the others exactly 0;
//   3. the weights are continuous in v: between cameras every term is a continuous function of
//      the s_j, and as θ_j → 0 for one camera w_j = 1 / (1 + Σ_{i≠j} (s_j / s_i)^(k/2)) → 1,
//      which is the value at coincidence.
// Computing s_i as |d_i − v|²/2 rather than 1 − d_i·v keeps its relative precision for small
// angles (s ≈ θ²/2 with full precision down to θ ≈ 1e−150).
#pragma once

#include <cstddef>

#include "common/core/mesh.h"

namespace tdvo {

// s = 1 − cos θ between two unit vectors, as |a − b|² / 2: exactly 0 when a == b.
double oneMinusCosine(const Vec3d& a, const Vec3d& b);

// The weights of `count` cameras from their s_i = 1 − cos θ_i (each in [0, 2]) and the
// sharpness k > 0 (formula above). Writes `count` weights to `weights`; count may be 0.
void viewWeights(const double* oneMinusCos, size_t count, double sharpness, double* weights);

// Unstructured-lumigraph-style weights (in the spirit of Buehler et al. 2001, "Unstructured
// Lumigraph Rendering"): per camera i, besides s_i, its resolution ratio r_i (camera i's texel
// footprint at the surface point over the virtual view's pixel footprint there) and its edge
// factor e_i in [0, 1] (0 on an edge of camera i's shape, 1 at EdgeWidth pixels from it or
// further). With β ≥ 0:
//
//   s'_i = s_i · (1 + β · max(0, r_i − 1))       (coarser texels count as a larger angle)
//   u_i  = viewWeights(s')_i · max(e_i, kEdgeFloor)
//   w_i  = u_i / Σ_j u_j
//
// Properties: w_i ≥ 0, Σ w_i = 1 (u has a positive term: the largest viewWeights term is
// ≥ 1/count, times ≥ kEdgeFloor); where s_j = 0 for one camera its weight is exactly 1 whatever
// r and e (viewWeights gives the others exactly 0); continuous in s, r and e (every factor is).
constexpr double kEdgeFloor = 1e-3;
void ulrWeights(const double* oneMinusCos, const double* resolution, const double* edge,
                size_t count, double sharpness, double resolutionPenalty, double* weights);

}  // namespace tdvo
