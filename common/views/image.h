// 8-bit images (PNG reading and writing: common/media/png_io.h).
//
// One simple type for camera frames, masks, textures and renders: width × height pixels of
// `channels` interleaved 8-bit samples (1 grey, 2 grey+alpha, 3 RGB, 4 RGBA), rows top to bottom.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tdvo {

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<uint8_t> pixels;  // row-major, channels interleaved: (y·width + x)·channels + c

  Image() = default;
  // A width × height image of `channels` samples per pixel, every sample set to `fill`.
  Image(int width, int height, int channels, uint8_t fill = 0);

  bool empty() const { return pixels.empty(); }
  size_t index(int x, int y, int c = 0) const {
    return (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) *
               static_cast<size_t>(channels) +
           static_cast<size_t>(c);
  }
  uint8_t& at(int x, int y, int c = 0) { return pixels[index(x, y, c)]; }
  uint8_t at(int x, int y, int c = 0) const { return pixels[index(x, y, c)]; }

  bool operator==(const Image& o) const {
    return width == o.width && height == o.height && channels == o.channels && pixels == o.pixels;
  }
  bool operator!=(const Image& o) const { return !(*this == o); }
};

// Converts between channel counts: grey ↔ RGB by replication / BT.601 luma
// ((77 R + 150 G + 29 B + 128) >> 8), alpha added as 255 or dropped.
Image convertChannels(const Image& image, int channels);

// Checks that a masked image comparison (`metric`, e.g. "PSNR", names it in the message) has
// what it needs: `test` and `reference` with at least three channels and a `mask` with at least
// one, all of one size. Throws Error otherwise.
void checkMaskedComparison(const Image& test, const Image& reference, const Image& mask,
                           const std::string& metric);

}  // namespace tdvo
