#include "common/media/png_io.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>

#include "common/core/error.h"
#include "common/core/file_io.h"

namespace tdvo {
namespace {

// libpng reports errors through longjmp. The functions below that call libpng keep only
// trivially destructible locals between setjmp and the calls, store the message in a plain
// buffer, and the C++ callers throw afterwards.
struct PngErrorState {
  char message[256] = {0};
};

void pngError(png_structp png, png_const_charp message) {
  auto* state = static_cast<PngErrorState*>(png_get_error_ptr(png));
  std::snprintf(state->message, sizeof state->message, "%s", message);
  png_longjmp(png, 1);
}

void pngWarning(png_structp, png_const_charp) {}

struct MemoryReader {
  const uint8_t* data;
  size_t size, pos;
};

void readFromMemory(png_structp png, png_bytep out, png_size_t length) {
  auto* reader = static_cast<MemoryReader*>(png_get_io_ptr(png));
  if (reader->size - reader->pos < length) png_error(png, "file is truncated");
  std::memcpy(out, reader->data + reader->pos, length);
  reader->pos += length;
}

struct DecodedHeader {
  png_uint_32 width = 0, height = 0;
  int channels = 0;
};

// Step 1: header and transformations; returns false on a libpng error.
bool decodeHeader(png_structp png, png_infop info, DecodedHeader& header) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_info(png, info);
  const int colourType = png_get_color_type(png, info);
  const int bitDepth = png_get_bit_depth(png, info);
  if (colourType == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (colourType == PNG_COLOR_TYPE_GRAY && bitDepth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
  if (bitDepth == 16) png_set_scale_16(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  header.width = png_get_image_width(png, info);
  header.height = png_get_image_height(png, info);
  header.channels = png_get_channels(png, info);
  return true;
}

// Step 2: the rows into `rows`; returns false on a libpng error.
bool decodeRows(png_structp png, png_infop info, png_bytep* rows) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_read_image(png, rows);
  png_read_end(png, info);
  return true;
}

struct ReadStructs {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~ReadStructs() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
};

}  // namespace

Image decodePng(const std::vector<uint8_t>& bytes, const std::string& name) {
  check(bytes.size() >= 8 && png_sig_cmp(bytes.data(), 0, 8) == 0,
        name + ": not a PNG file (bad signature)");
  PngErrorState errorState;
  ReadStructs s;
  s.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &errorState, pngError, pngWarning);
  check(s.png != nullptr, name + ": cannot initialise libpng");
  s.info = png_create_info_struct(s.png);
  check(s.info != nullptr, name + ": cannot initialise libpng");
  // Refuse absurd sizes before allocating (corrupt or hostile headers).
  png_set_user_limits(s.png, 1u << 15, 1u << 15);
  MemoryReader reader{bytes.data(), bytes.size(), 0};
  png_set_read_fn(s.png, &reader, readFromMemory);

  DecodedHeader header;
  if (!decodeHeader(s.png, s.info, header))
    throw Error(name + ": cannot read PNG: " + errorState.message);
  check(header.channels >= 1 && header.channels <= 4,
        name + ": unsupported PNG channel count " + std::to_string(header.channels));
  // Deflate expands at most 1032:1, no PNG pixel is stored in less than 1 bit and a decoded one
  // takes at most 4 bytes, so n bytes of file hold at most 32 * 1032 * n bytes of samples.
  // Checked before allocating: a 69-byte file declaring 32767 x 32767 RGBA must not ask for 4 GB.
  const uint64_t samples = uint64_t{header.width} * header.height * uint64_t(header.channels);
  check(samples <= uint64_t{32 * 1032} * bytes.size(),
        name + ": PNG declares " + std::to_string(header.width) + "x" +
            std::to_string(header.height) + " pixels, more than its " +
            std::to_string(bytes.size()) + " bytes can hold");
  Image image(static_cast<int>(header.width), static_cast<int>(header.height), header.channels);
  std::vector<png_bytep> rows(header.height);
  for (png_uint_32 y = 0; y < header.height; ++y)
    rows[y] = image.pixels.data() + image.index(0, static_cast<int>(y));
  if (!decodeRows(s.png, s.info, rows.data()))
    throw Error(name + ": cannot read PNG: " + errorState.message);
  return image;
}

Image readPng(const std::string& path) {
  return decodePng(readFileBytes(path), path);
}

void readPngSize(const std::string& path, int& width, int& height) {
  // Signature (8) + IHDR length and type (8) + width and height (8).
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw Error(path + ": cannot open");
  noteFileRead(f);
  uint8_t head[24];
  const size_t n = std::fread(head, 1, sizeof head, f);
  std::fclose(f);
  check(n == sizeof head && png_sig_cmp(head, 0, 8) == 0, path + ": not a PNG file");
  check(std::memcmp(head + 12, "IHDR", 4) == 0, path + ": PNG does not start with IHDR");
  auto be32 = [](const uint8_t* p) {
    return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | p[3];
  };
  const uint32_t w = be32(head + 16), h = be32(head + 20);
  check(w > 0 && h > 0 && w < (1u << 15) && h < (1u << 15),
        path + ": PNG size " + std::to_string(w) + "x" + std::to_string(h) + " out of range");
  width = static_cast<int>(w);
  height = static_cast<int>(h);
}

namespace {

void writeToVector(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
  out->insert(out->end(), data, data + length);
}

void flushNothing(png_structp) {}

bool encodeRows(png_structp png, png_infop info, const Image& image, png_bytep* rows,
                PngEffort effort) {
  if (setjmp(png_jmpbuf(png))) return false;
  static const int kColourType[5] = {0, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA,
                                     PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA};
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width),
               static_cast<png_uint_32>(image.height), 8, kColourType[image.channels],
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (effort == PngEffort::kFast) {
    png_set_compression_level(png, 1);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
  } else {
    png_set_compression_level(png, 6);
  }
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, info);
  return true;
}

struct WriteStructs {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~WriteStructs() { png_destroy_write_struct(&png, info ? &info : nullptr); }
};

}  // namespace

std::vector<uint8_t> encodePng(const Image& image, PngEffort effort) {
  check(image.width > 0 && image.height > 0 && image.channels >= 1 && image.channels <= 4 &&
            image.pixels.size() == image.index(0, image.height),
        "encodePng: invalid image " + std::to_string(image.width) + "x" +
            std::to_string(image.height) + "x" + std::to_string(image.channels));
  PngErrorState errorState;
  WriteStructs s;
  s.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &errorState, pngError, pngWarning);
  check(s.png != nullptr, "encodePng: cannot initialise libpng");
  s.info = png_create_info_struct(s.png);
  check(s.info != nullptr, "encodePng: cannot initialise libpng");
  std::vector<uint8_t> out;
  out.reserve(image.pixels.size() / 2 + 1024);
  png_set_write_fn(s.png, &out, writeToVector, flushNothing);
  std::vector<png_bytep> rows(static_cast<size_t>(image.height));
  for (int y = 0; y < image.height; ++y)
    rows[static_cast<size_t>(y)] = const_cast<png_bytep>(&image.pixels[image.index(0, y)]);
  if (!encodeRows(s.png, s.info, image, rows.data(), effort))
    throw Error(std::string("encodePng: ") + errorState.message);
  return out;
}

void writePng(const std::string& path, const Image& image) {
  const std::vector<uint8_t> bytes = encodePng(image);
  writeFileAtomic(path, bytes.data(), bytes.size());
}

}  // namespace tdvo
