#include "encoder/texture_padding.h"

#include <cstdint>
#include <vector>

#include "common/core/error.h"

namespace tdvo {

namespace {

// One plane with its inside/outside flags.
struct Plane {
  int width, height;
  uint8_t* samples;
  std::vector<uint8_t> inside;
  uint8_t& at(int x, int y) { return samples[static_cast<size_t>(y) * width + x]; }
  bool in(int x, int y) const { return inside[static_cast<size_t>(y) * width + x] != 0; }
};

// Fills the outside samples of one line (`count` samples at stride `step` from `start`) from
// its inside ones; marks them filled. Returns false if the line has no inside sample.
template <class Get, class Set>
bool padLine(int count, Get isInside, Set value) {
  int previous = -1;
  bool any = false;
  for (int i = 0; i <= count; ++i) {
    if (i < count && !isInside(i)) continue;
    // Samples previous+1 .. i-1 are outside; fill them from the neighbours that exist.
    if (i - previous > 1) {
      if (previous < 0 && i == count) return false;  // no inside sample at all
      for (int j = previous + 1; j < i; ++j) {
        if (previous < 0)
          value(j, value(i, -1));
        else if (i == count)
          value(j, value(previous, -1));
        else
          value(j, (value(previous, -1) + value(i, -1) + 1) / 2);
      }
    }
    previous = i;
    any = true;
  }
  return any;
}

// MPEG-4-style repetitive padding of one block of a plane (rows, then still-empty rows from
// the columns).
void padBlock(Plane& p, int bx, int by, int size) {
  const int w = std::min(size, p.width - bx), h = std::min(size, p.height - by);
  std::vector<uint8_t> rowFilled(h, 0);
  for (int r = 0; r < h; ++r) {
    const int y = by + r;
    rowFilled[r] = padLine(
        w, [&](int i) { return p.in(bx + i, y); },
        [&](int i, int v) -> int {
          if (v >= 0) p.at(bx + i, y) = static_cast<uint8_t>(v);
          return p.at(bx + i, y);
        });
  }
  for (int c = 0; c < w; ++c) {
    const int x = bx + c;
    padLine(
        h, [&](int i) { return rowFilled[i] != 0; },
        [&](int i, int v) -> int {
          if (v >= 0) p.at(x, by + i) = static_cast<uint8_t>(v);
          return p.at(x, by + i);
        });
  }
}

}  // namespace

YuvPicture prepareTexture(const Image& frame, const Image& shape, const TextureBox& box,
                          TexturePadding padding) {
  check(frame.channels == 3 && shape.channels == 1 && frame.width == shape.width &&
            frame.height == shape.height,
        "prepareTexture: frame and shape disagree");
  check(!box.empty() && box.width % kMacroblockSize == 0 && box.height % kMacroblockSize == 0,
        "prepareTexture: the box must be whole macroblocks");
  Image cut(box.width, box.height, 3, 128);
  Plane luma{box.width, box.height, nullptr, std::vector<uint8_t>(size_t(box.width) * box.height)};
  for (int y = 0; y < box.height; ++y)
    for (int x = 0; x < box.width; ++x) {
      const int fx = box.x + x, fy = box.y + y;
      if (fx >= frame.width || fy >= frame.height) continue;
      for (int c = 0; c < 3; ++c)
        cut.at(x, y, c) = frame.at(fx, fy, c);
      luma.inside[size_t(y) * box.width + x] = shape.at(fx, fy) != 0;
    }
  YuvPicture picture = rgbToYuv420(cut);
  if (padding == TexturePadding::kNone) return picture;

  luma.samples = picture.y.data();
  const int cw = picture.chromaWidth(), ch = picture.chromaHeight();
  Plane cb{cw, ch, picture.u.data(), std::vector<uint8_t>(size_t(cw) * ch)};
  Plane cr{cw, ch, picture.v.data(), {}};
  for (int y = 0; y < ch; ++y)
    for (int x = 0; x < cw; ++x)
      cb.inside[size_t(y) * cw + x] = luma.in(2 * x, 2 * y) || luma.in(2 * x + 1, 2 * y) ||
                                      luma.in(2 * x, 2 * y + 1) || luma.in(2 * x + 1, 2 * y + 1);
  cr.inside = cb.inside;

  const int half = kMacroblockSize / 2;
  for (int my = 0; my < box.height; my += kMacroblockSize)
    for (int mx = 0; mx < box.width; mx += kMacroblockSize) {
      bool touched = false, full = true;
      for (int y = my; y < my + kMacroblockSize; ++y)
        for (int x = mx; x < mx + kMacroblockSize; ++x) {
          touched = touched || luma.in(x, y);
          full = full && luma.in(x, y);
        }
      if (!touched) {
        for (int y = my; y < my + kMacroblockSize; ++y)
          for (int x = mx; x < mx + kMacroblockSize; ++x)
            luma.at(x, y) = 128;
        for (int y = my / 2; y < my / 2 + half; ++y)
          for (int x = mx / 2; x < mx / 2 + half; ++x)
            cb.at(x, y) = cr.at(x, y) = 128;
      } else if (!full && padding == TexturePadding::kExtrapolate) {
        padBlock(luma, mx, my, kMacroblockSize);
        padBlock(cb, mx / 2, my / 2, half);
        padBlock(cr, mx / 2, my / 2, half);
      }
    }
  return picture;
}

}  // namespace tdvo
