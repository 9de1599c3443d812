// Procedural meshes the project makes itself: the bundled default sample, test inputs and the
// synthetic capture rig's default object, so that nothing needs downloaded data.
#pragma once

#include <vector>

#include "common/core/mesh.h"

namespace tdvo {

// A unit icosphere: an icosahedron whose faces are split into four `subdivisions` times, with
// the new vertices pushed onto the sphere (10 * 4^s + 2 vertices, 20 * 4^s triangles).
Mesh icosphere(int subdivisions);

// A time-consistent deforming "blob": the icosphere stretched by travelling waves, bending and
// moving sideways, `frames` frames of a loop. Same connectivity in every frame. Deterministic.
std::vector<Mesh> deformingBlob(int subdivisions, int frames);

}  // namespace tdvo
