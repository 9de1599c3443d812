// The shape of the object in each camera, shared by texture encoder and decoder.
//
// The shape is never transmitted: both sides rasterise the *decoded* mesh (dequantised from the
// grid) into each camera with the deterministic rasteriser (common/views/rasteriser.h), so they get
// the same mask. The texture box is transmitted: a rectangle of whole 16×16 macroblocks, on the
// camera frame's macroblock grid, that the H.264 pictures of that camera cover.
#pragma once

#include "common/core/grid.h"
#include "common/core/mesh.h"
#include "common/views/camera.h"
#include "common/views/image.h"
#include "common/views/rasteriser.h"

namespace tdvo {

constexpr int kMacroblockSize = 16;

struct TextureBox {
  int x = 0, y = 0;           // top-left pixel in the camera frame, multiples of 16
  int width = 0, height = 0;  // multiples of 16; may reach past the frame's right/bottom edge
  bool empty() const { return width == 0 || height == 0; }
  bool operator==(const TextureBox& o) const {
    return x == o.x && y == o.y && width == o.width && height == o.height;
  }
};

// The object mask (255 inside, 0 outside) of a decoded mesh seen by `camera`.
Image textureShape(const IntMesh& decoded, const Grid& grid, const Camera& camera);
// The same from the decoded mesh already dequantised (grid.dequantise(decoded)) and the
// camera's rasteriser set up once (MaskRenderer(camera)): what encoder and decoder use, frame
// after frame, so that the cameras of a frame share one dequantisation and every frame of a
// camera one set-up.
Image textureShape(const Mesh& dequantised, const MaskRenderer& camera);

// The smallest macroblock-aligned box containing every non-zero pixel of `mask`, grown by
// `margin` pixels first (clipped to the frame); empty if the mask is empty.
TextureBox macroblockBox(const Image& mask, int margin);
// The smallest macroblock-aligned box containing both.
TextureBox unite(const TextureBox& a, const TextureBox& b);
// The whole frame, rounded up to whole macroblocks.
TextureBox fullFrameBox(int width, int height);

}  // namespace tdvo
