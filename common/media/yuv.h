// YUV 4:2:0 pictures: what the texture coder codes. Conversion from and to RGB goes through
// FFmpeg's libswscale with a fixed, documented set-up (docs/textures.md): ITU-R BT.601
// coefficients, limited ("TV") range, chroma sited at the centre of each 2×2 luma block,
// bit-exact mode. The MD5 of a decoded picture covers its planes, not any RGB conversion.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/core/md5.h"
#include "common/views/image.h"

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

// RGB (3 channels) to YUV 4:2:0; the image's width and height must be even.
YuvPicture rgbToYuv420(const Image& rgb);
// YUV 4:2:0 to RGB (3 channels).
Image yuv420ToRgb(const YuvPicture& picture);

// MD5 over the Y, U and V planes, in that order, rows top to bottom without padding
// (docs/bitstream.md, "Frame hashes").
Md5Digest pictureDigest(const YuvPicture& picture);

// "MD5 frame=<n> texture cam=<c> <32 hex digits>", printed by encoder and decoder per camera
// and frame.
std::string textureHashLine(int frame, int camera, const YuvPicture& picture);

}  // namespace tdvo
