// Clean-up of the marching cubes surface: connected components, first-order neighbourhood
// (umbrella) smoothing and edge-collapse decimation driven by the normals of adjacent faces.
// Smoothing and decimation are OpenMesh's (Smoother::JacobiLaplaceSmootherT and
// Decimater::DecimaterT with ModNormalDeviationT); this file converts to and from its mesh type.
#pragma once

#include <cstddef>

#include "common/core/mesh.h"

namespace tdvo {

// Merges vertices at exactly the same position (e.g. the seams of a texture atlas, where a
// published mesh is split into charts), keeping the first of each group in vertex order, and
// drops triangles that lose a corner to the merge. Returns the number of vertices removed.
size_t weldVertices(Mesh& mesh);

// Keeps the connected component (vertices joined by triangle edges) with the most triangles;
// vertices no triangle uses are dropped. Returns the number of components the mesh had.
size_t keepLargestComponent(Mesh& mesh);

struct SmoothingOptions {
  int iterations = 3;          // umbrella iterations; 0: none
  double maxDisplacement = 0;  // no vertex moves farther than this along its input normal
                               // (world units; OpenMesh's local error check); 0: unlimited
};

// Umbrella smoothing: each iteration moves every vertex to the mean of its one-ring
// neighbours (Jacobi update; tangential and normal components).
void smoothMesh(Mesh& mesh, const SmoothingOptions& options);

struct DecimationOptions {
  size_t targetFaces = 0;          // stop at this many triangles; 0: only the error bounds stop it
  double maxNormalDeviation = 20;  // degrees: collapses that would spread the normals of any
                                   // affected face's collapsed history wider are refused
  double maxError = 0;             // quadric error bound (squared world units); 0: none
};

// Edge-collapse decimation. Collapses are taken in order of the normal deviation they cause
// (smallest first) and refused when the deviation exceeds maxNormalDeviation or the quadric
// error exceeds maxError. Returns the number of collapses made.
size_t decimateMesh(Mesh& mesh, const DecimationOptions& options);

// Number of triangles OpenMesh could not take because they would make the mesh non-manifold
// (a complex vertex or edge), for the last smoothMesh / decimateMesh call on this thread. Such
// triangles are dropped.
size_t lastDroppedTriangles();

}  // namespace tdvo
