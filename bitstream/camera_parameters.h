// Conversions between the camera model (common/views/camera.h) and its syntax structure. The
// doubles are carried bit for bit, so encoder and decoder project with identical cameras.
#pragma once

#include "bitstream/syntax.h"
#include "common/views/camera.h"
#include "common/views/texture_shape.h"

namespace tdvo {

inline CameraParameters toParameters(const Camera& camera, const TextureBox& box) {
  CameraParameters c;
  c.cam_name = camera.name;
  c.cam_width = static_cast<uint16_t>(camera.width);
  c.cam_height = static_cast<uint16_t>(camera.height);
  c.cam_fx = camera.fx;
  c.cam_fy = camera.fy;
  c.cam_cx = camera.cx;
  c.cam_cy = camera.cy;
  c.cam_k1 = camera.distortion.k1;
  c.cam_k2 = camera.distortion.k2;
  c.cam_p1 = camera.distortion.p1;
  c.cam_p2 = camera.distortion.p2;
  c.cam_k3 = camera.distortion.k3;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      c.cam_rotation[3 * r + k] = camera.R[r][k];
  for (int k = 0; k < 3; ++k)
    c.cam_translation[k] = camera.t[k];
  c.tx_box_x = static_cast<uint16_t>(box.x);
  c.tx_box_y = static_cast<uint16_t>(box.y);
  c.tx_box_width = static_cast<uint16_t>(box.width);
  c.tx_box_height = static_cast<uint16_t>(box.height);
  return c;
}

// `index` names a camera without a name ("cam<index>"; every stream camera has one).
inline Camera toCamera(const CameraParameters& c, int index) {
  Camera camera;
  camera.name = c.cam_name.empty() ? "cam" + std::to_string(index) : c.cam_name;
  camera.width = c.cam_width;
  camera.height = c.cam_height;
  camera.fx = c.cam_fx;
  camera.fy = c.cam_fy;
  camera.cx = c.cam_cx;
  camera.cy = c.cam_cy;
  camera.distortion = {c.cam_k1, c.cam_k2, c.cam_p1, c.cam_p2, c.cam_k3};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      camera.R[r][k] = c.cam_rotation[3 * r + k];
  for (int k = 0; k < 3; ++k)
    camera.t[k] = c.cam_translation[k];
  return camera;
}

inline TextureBox textureBox(const CameraParameters& c) {
  return {c.tx_box_x, c.tx_box_y, c.tx_box_width, c.tx_box_height};
}

}  // namespace tdvo
