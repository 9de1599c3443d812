// 8-bit images and PNG reading/writing (through libpng).
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

// Reads a PNG file of any colour type and bit depth into 8-bit samples: palettes are expanded
// to RGB(A), bit depths below 8 are scaled up, 16-bit samples are rounded to 8 bits, and a tRNS
// chunk becomes an alpha channel. No gamma or colour-space conversion is applied. Throws Error
// naming the file for anything unreadable, and, before allocating, for a declared size (at most
// 32767 x 32767) larger than the file's bytes can hold (33,024 decoded bytes per file byte).
Image readPng(const std::string& path);
// The same for PNG bytes in memory; `name` is used in error messages only.
Image decodePng(const std::vector<uint8_t>& bytes, const std::string& name);
// Reads only the header: the image size, without decoding the pixels.
void readPngSize(const std::string& path, int& width, int& height);

// How hard encodePng compresses; the pixels are the same either way.
//   kSmall  zlib level 6 and libpng's adaptive row filters (all five tried per row)
//   kFast   zlib level 1 and the Up filter on every row: on decoded camera frames about 3.7x
//           faster than kSmall, the files about 30 % larger (docs/performance.md, "Textures")
enum class PngEffort { kSmall, kFast };

// Encodes an image as PNG (8-bit, colour type from `channels`, no time or text chunks): the
// same image always gives the same bytes with the same libpng/zlib and effort.
std::vector<uint8_t> encodePng(const Image& image, PngEffort effort = PngEffort::kSmall);
// Writes a PNG file atomically (temporary name, then rename).
void writePng(const std::string& path, const Image& image);

// Converts between channel counts: grey ↔ RGB by replication / BT.601 luma
// ((77 R + 150 G + 29 B + 128) >> 8), alpha added as 255 or dropped.
Image convertChannels(const Image& image, int channels);

}  // namespace tdvo
