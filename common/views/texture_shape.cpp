#include "common/views/texture_shape.h"

#include <algorithm>

#include "common/views/rasteriser.h"

namespace tdvo {

namespace {

int roundDownToMacroblock(int v) {
  return v / kMacroblockSize * kMacroblockSize;
}
int roundUpToMacroblock(int v) {
  return (v + kMacroblockSize - 1) / kMacroblockSize * kMacroblockSize;
}

}  // namespace

Image textureShape(const IntMesh& decoded, const Grid& grid, const Camera& camera) {
  return renderMask(grid.dequantise(decoded), camera);
}

Image textureShape(const Mesh& dequantised, const MaskRenderer& camera) {
  return camera.render(dequantised);
}

TextureBox macroblockBox(const Image& mask, int margin) {
  int x0 = mask.width, y0 = mask.height, x1 = -1, y1 = -1;
  for (int y = 0; y < mask.height; ++y)
    for (int x = 0; x < mask.width; ++x)
      if (mask.at(x, y) != 0) {
        x0 = std::min(x0, x);
        y0 = std::min(y0, y);
        x1 = std::max(x1, x);
        y1 = std::max(y1, y);
      }
  if (x1 < 0) return {};
  x0 = std::max(0, x0 - margin);
  y0 = std::max(0, y0 - margin);
  x1 = std::min(mask.width - 1, x1 + margin);
  y1 = std::min(mask.height - 1, y1 + margin);
  TextureBox box;
  box.x = roundDownToMacroblock(x0);
  box.y = roundDownToMacroblock(y0);
  box.width = roundUpToMacroblock(x1 + 1) - box.x;
  box.height = roundUpToMacroblock(y1 + 1) - box.y;
  return box;
}

TextureBox unite(const TextureBox& a, const TextureBox& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  TextureBox out;
  out.x = std::min(a.x, b.x);
  out.y = std::min(a.y, b.y);
  out.width = std::max(a.x + a.width, b.x + b.width) - out.x;
  out.height = std::max(a.y + a.height, b.y + b.height) - out.y;
  return out;
}

TextureBox fullFrameBox(int width, int height) {
  return {0, 0, roundUpToMacroblock(width), roundUpToMacroblock(height)};
}

}  // namespace tdvo
