// Virtual camera paths for free-viewpoint output: an orbit around the object, or a list of poses
// from a file (docs/rendering.md, "Camera paths").
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/core/mesh.h"
#include "common/media/dataset.h"
#include "common/views/camera.h"

namespace tdvo {

// The intrinsics of the virtual camera: width × height 0 takes camera 0's size and intrinsics
// (without its lens distortion); otherwise the given size, the principal point at the image
// centre and fx = fy from the horizontal field of view in degrees (camera 0's focal length, scaled
// to the new width, when fieldOfView is 0).
Camera virtualIntrinsics(const Dataset& dataset, int width, int height, double fieldOfView);

// The world's up direction: the dataset's `up` when it has one, else the mean of the cameras'
// image-up directions (−y axes), normalised.
Vec3d datasetUp(const Dataset& dataset);

// The centre of a mesh's bounding box.
Vec3d boundingBoxCentre(const Mesh& mesh);

struct OrbitParams {
  int steps = 36;                   // cameras on the orbit, evenly spaced in azimuth
  std::optional<double> elevation;  // degrees above the centre; none: the cameras' mean
  double distance = 0;              // from the centre; 0: the cameras' mean distance
  double turns = 1;                 // full turns over the steps
};

// A circle of cameras around `centre`, all looking at it, with image-up as close to `up` as
// possible. Step 0 lies at camera 0's azimuth; step k at k · turns · 360° / steps further,
// counter-clockwise seen from above.
std::vector<Camera> orbitPath(const Dataset& dataset, const Vec3d& centre, const Vec3d& up,
                              const Camera& intrinsics, const OrbitParams& params);

// Poses from a file. A `.json` file is read as a dataset (common/media/dataset.h) and its cameras
// are the poses, intrinsics and distortion included. Any other file is text: one pose per line,
// `eye_x eye_y eye_z  target_x target_y target_z` with an optional `up_x up_y up_z` (default
// `up`), camera looking from the eye at the target with the given intrinsics; blank lines and
// `#` comments are skipped. Errors name the file and line.
std::vector<Camera> readPoses(const std::string& path, const Camera& intrinsics, const Vec3d& up);

}  // namespace tdvo
