// Texture coding parts: YUV conversion, the texture box, padding, and the H.264 round trip
// through x264 and FFmpeg.
#include <gtest/gtest.h>

#include <cmath>

#include "common/core/error.h"
#include "common/media/yuv.h"
#include "common/views/texture_shape.h"
#include "decoder/texture/h264_decoder.h"
#include "encoder/h264_encoder.h"
#include "encoder/texture_padding.h"

namespace tdvo {
namespace {

// A smooth colourful test frame and a disc-shaped object mask.
Image testFrame(int w, int h, int phase = 0) {
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      img.at(x, y, 0) = static_cast<uint8_t>((x * 3 + phase) % 256);
      img.at(x, y, 1) = static_cast<uint8_t>((y * 5 + 2 * phase) % 256);
      img.at(x, y, 2) = static_cast<uint8_t>(128 + 100 * std::sin((x + y + phase) * 0.05));
    }
  return img;
}

Image disc(int w, int h, double cx, double cy, double r) {
  Image mask(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (std::hypot(x + 0.5 - cx, y + 0.5 - cy) < r) mask.at(x, y) = 255;
  return mask;
}

TEST(Yuv, RoundTripIsCloseAndGreyIsExact) {
  const Image rgb = testFrame(64, 48);
  const Image back = yuv420ToRgb(rgbToYuv420(rgb));
  double squared = 0;
  for (size_t i = 0; i < rgb.pixels.size(); ++i)
    squared += std::pow(double(rgb.pixels[i]) - back.pixels[i], 2);
  const double psnr = 10 * std::log10(255.0 * 255.0 / (squared / rgb.pixels.size()));
  EXPECT_GT(psnr, 30.0);  // chroma subsampling of a smooth image
  // Limited-range BT.601: mid-grey RGB 128 is Y = 126 (16 + 219·128/255), Cb = Cr = 128.
  const YuvPicture grey = rgbToYuv420(Image(16, 16, 3, 128));
  EXPECT_EQ(grey.y[0], 126);
  EXPECT_EQ(grey.u[0], 128);
  EXPECT_EQ(grey.v[0], 128);
}

// Sizes whose rows are not a multiple of libswscale's vector width: it loads and stores past a
// row's end, and on tightly packed planes it overflowed the heap (glibc aborted in free() at
// 4 x 6; valgrind saw invalid reads at 322 x 242). Each conversion is the same whatever the
// row padding: a grey picture stays exactly grey, a pattern close, and the result repeats.
TEST(Yuv, AwkwardSizesStayInTheirPlanes) {
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{
           {2, 2}, {2, 8}, {2, 12}, {4, 6}, {4, 10}, {6, 2}, {34, 18}, {322, 242}, {100, 76}}) {
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    for (int round = 0; round < 3; ++round) {
      const YuvPicture grey = rgbToYuv420(Image(w, h, 3, 128));
      for (uint8_t y : grey.y)
        ASSERT_EQ(y, 126);
      for (uint8_t c : grey.u)
        ASSERT_EQ(c, 128);
      const Image back = yuv420ToRgb(grey);
      for (uint8_t p : back.pixels)
        ASSERT_NEAR(p, 128, 1);
      const Image pattern = testFrame(w, h, round);
      EXPECT_EQ(yuv420ToRgb(rgbToYuv420(pattern)).pixels, yuv420ToRgb(rgbToYuv420(pattern)).pixels);
    }
  }
}

TEST(TextureBox, MacroblockAlignedAndUnited) {
  Image mask(100, 60, 1);
  mask.at(20, 17) = 255;
  mask.at(40, 33) = 255;
  const TextureBox box = macroblockBox(mask, 0);
  EXPECT_EQ(box, (TextureBox{16, 16, 32, 32}));
  const TextureBox grown = macroblockBox(mask, 5);  // 15..45 x 12..38
  EXPECT_EQ(grown, (TextureBox{0, 0, 48, 48}));
  EXPECT_TRUE(macroblockBox(Image(10, 10, 1), 3).empty());
  EXPECT_EQ(unite({16, 16, 16, 16}, {48, 0, 16, 64}), (TextureBox{16, 0, 48, 64}));
  EXPECT_EQ(fullFrameBox(644, 486), (TextureBox{0, 0, 656, 496}));
}

TEST(TexturePadding, Mb128AndExtrapolateOnlyTouchTheOutside) {
  const int w = 96, h = 64;
  const Image frame = testFrame(w, h);
  const Image shape = disc(w, h, 40, 30, 14);
  const TextureBox box = fullFrameBox(w, h);
  const YuvPicture none = prepareTexture(frame, shape, box, TexturePadding::kNone);
  const YuvPicture mb128 = prepareTexture(frame, shape, box, TexturePadding::kMb128);
  const YuvPicture extra = prepareTexture(frame, shape, box, TexturePadding::kExtrapolate);
  ASSERT_EQ(none.width, box.width);
  int changedInside = 0, greyMacroblocks = 0;
  for (int y = 0; y < box.height; ++y)
    for (int x = 0; x < box.width; ++x) {
      const size_t i = size_t(y) * box.width + x;
      if (shape.at(box.x + x, box.y + y)) {
        changedInside += mb128.y[i] != none.y[i];
        changedInside += extra.y[i] != none.y[i];
      }
    }
  EXPECT_EQ(changedInside, 0);
  // Macroblocks the shape does not touch are grey in both padded modes.
  for (int my = 0; my < box.height; my += 16)
    for (int mx = 0; mx < box.width; mx += 16) {
      bool touched = false;
      for (int y = my; y < my + 16; ++y)
        for (int x = mx; x < mx + 16; ++x)
          touched = touched || shape.at(box.x + x, box.y + y);
      if (touched) continue;
      ++greyMacroblocks;
      for (int y = my; y < my + 16; ++y)
        for (int x = mx; x < mx + 16; ++x) {
          EXPECT_EQ(mb128.y[size_t(y) * box.width + x], 128);
          EXPECT_EQ(extra.y[size_t(y) * box.width + x], 128);
        }
    }
  EXPECT_GT(greyMacroblocks, 0);
  // In boundary macroblocks the extrapolated outside pixels repeat the shape's edge: a pixel
  // just left of the disc on its middle row equals its right neighbour inside.
  const int row = 30;
  int x = 0;
  while (!shape.at(x + 1, row))
    ++x;             // x: the last pixel outside, left of the disc
  ASSERT_GT(x, 16);  // inside the disc's boundary macroblock, not a grey one
  EXPECT_EQ(extra.y[size_t(row) * box.width + x], extra.y[size_t(row) * box.width + x + 1]);
}

TEST(H264, RoundTripIsDeterministicAndIdrsDecodeAlone) {
  H264Settings s;
  s.width = 64;
  s.height = 48;
  s.qp = 26;
  s.preset = "fast";
  std::vector<std::vector<uint8_t>> units, again;
  std::vector<YuvPicture> pictures;
  for (int pass = 0; pass < 2; ++pass) {
    H264Encoder encoder(s);
    for (int f = 0; f < 6; ++f) {
      const YuvPicture p = rgbToYuv420(testFrame(64, 48, 4 * f));
      if (pass == 0) pictures.push_back(p);
      (pass == 0 ? units : again).push_back(encoder.encode(p, f == 0 || f == 3));
    }
  }
  EXPECT_EQ(units, again);  // same input, same bytes
  H264Decoder decoder("test");
  std::vector<YuvPicture> decoded;
  for (const auto& au : units)
    decoded.push_back(decoder.decode(au, 64, 48));
  for (size_t f = 0; f < decoded.size(); ++f) {
    double squared = 0;
    for (size_t i = 0; i < decoded[f].y.size(); ++i)
      squared += std::pow(double(decoded[f].y[i]) - pictures[f].y[i], 2);
    EXPECT_GT(10 * std::log10(255.0 * 255.0 * decoded[f].y.size() / squared), 30.0);
  }
  // Decoding from the second IDR alone gives the same pictures (a GOM is a random-access point).
  H264Decoder fresh("test");
  for (size_t f = 3; f < units.size(); ++f)
    EXPECT_EQ(fresh.decode(units[f], 64, 48), decoded[f]);
  // A corrupted access unit is an error, not a crash.
  std::vector<uint8_t> bad = units[1];
  for (size_t i = 8; i < bad.size(); ++i)
    bad[i] ^= 0x55;
  H264Decoder third("test");
  third.decode(units[0], 64, 48);
  EXPECT_THROW(third.decode(bad, 64, 48), Error);
}

}  // namespace
}  // namespace tdvo
