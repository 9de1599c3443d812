// Virtual camera paths for free-viewpoint output: an orbit around the object (by default within
// the arc the cameras span), or a list of poses from a file (docs/rendering.md, "Camera paths").
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

// The arc of azimuths about the axis `up` through `centre` that the cameras span: the smallest
// arc holding every camera's azimuth, i.e. the complement of the widest gap between neighbouring
// cameras (docs/rendering.md, "Camera paths"; tools/player/src/view_path.js takes the same arc).
// Azimuths are in radians, counter-clockwise seen from above, from camera 0's direction.
struct CameraArc {
  double start = 0;      // the azimuth of the camera just after the widest gap, in [0, 2π)
  double span = 0;       // counter-clockwise from `start` to the last camera, in [0, 2π)
  double widestGap = 0;  // 2π − span
  // The cameras surround the centre: widestGap < 1.5 × the mean spacing 2π / cameras and
  // < 100° (every azimuth within 50° of a camera; never with fewer than 4 cameras).
  bool surrounds = false;
};
CameraArc cameraArc(const Dataset& dataset, const Vec3d& centre, const Vec3d& up);

struct OrbitParams {
  int steps = 36;                   // cameras on the path
  std::optional<double> elevation;  // degrees above the centre; none: the cameras' mean
  double distance = 0;              // from the centre; 0: the cameras' mean distance
  std::optional<double> turns;      // full turns over the steps; none: the cameras' arc
};

// Cameras around `centre` at one distance and elevation, all looking at it, with image-up as
// close to `up` as possible. With `turns`, step 0 lies at camera 0's azimuth and step k at
// k · turns · 360° / steps further, counter-clockwise seen from above. Without, the steps stay
// within cameraArc(): a full turn as with turns = 1 when the cameras surround the centre; else
// evenly spaced from the arc's start (step 0) to its end (the last step; one step: its middle).
std::vector<Camera> orbitPath(const Dataset& dataset, const Vec3d& centre, const Vec3d& up,
                              const Camera& intrinsics, const OrbitParams& params);

// The largest width and height of a rendered view (--Width, --Height, a pose file's cameras).
constexpr int kMaxViewSize = 16384;

// Poses from a file. A `.json` file is read as a dataset (common/media/dataset.h) and its cameras
// are the poses, intrinsics and distortion included (image sizes at most kMaxViewSize). Any other
// file is text: one pose per line, `eye_x eye_y eye_z  target_x target_y target_z` with an optional
// `up_x up_y up_z` (default `up`), camera looking from the eye at the target with the given
// intrinsics; blank lines and
// `#` comments are skipped. Errors name the file and line.
std::vector<Camera> readPoses(const std::string& path, const Camera& intrinsics, const Vec3d& up);

}  // namespace tdvo
