// PNG reading and writing (through libpng) of 8-bit images (common/views/image.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/views/image.h"

namespace tdvo {

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

}  // namespace tdvo
