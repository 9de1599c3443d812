// YUV 4:2:0 pictures, the texture coder's pictures, and their MD5 (no library beyond the core;
// RGB conversion: common/media/yuv.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/core/md5.h"

namespace tdvo {

struct YuvPicture {
  int width = 0, height = 0;     // luma size; both even
  std::vector<uint8_t> y, u, v;  // tightly packed planes: width×height, (width/2)×(height/2) ×2

  YuvPicture() = default;
  YuvPicture(int width, int height, uint8_t fill = 128);
  int chromaWidth() const { return width / 2; }
  int chromaHeight() const { return height / 2; }
  bool operator==(const YuvPicture& o) const {
    return width == o.width && height == o.height && y == o.y && u == o.u && v == o.v;
  }
};

// MD5 over the Y, U and V planes, in that order, rows top to bottom without padding
// (docs/bitstream.md, "Frame hashes").
Md5Digest pictureDigest(const YuvPicture& picture);

// "MD5 frame=<n> texture cam=<c> <32 hex digits>", printed by encoder and decoder per camera
// and frame.
std::string textureHashLine(int frame, int camera, const YuvPicture& picture);

}  // namespace tdvo
