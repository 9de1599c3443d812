#include "common/media/yuv.h"

extern "C" {
#include <libswscale/swscale.h>
}

#include <memory>

#include "common/core/error.h"
#include "common/media/padded_plane.h"

namespace tdvo {

namespace {

struct SwsDeleter {
  void operator()(SwsContext* c) const { sws_freeContext(c); }
};

// One conversion between packed RGB24 and planar YUV 4:2:0 with the documented set-up.
std::unique_ptr<SwsContext, SwsDeleter> converter(int width, int height, AVPixelFormat from,
                                                  AVPixelFormat to) {
  const int flags =
      SWS_BILINEAR | SWS_ACCURATE_RND | SWS_BITEXACT | SWS_FULL_CHR_H_INT | SWS_FULL_CHR_H_INP;
  std::unique_ptr<SwsContext, SwsDeleter> c(
      sws_getContext(width, height, from, width, height, to, flags, nullptr, nullptr, nullptr));
  if (!c)
    throw Error("libswscale cannot convert " + std::to_string(width) + "x" +
                std::to_string(height) + " pictures");
  const int* bt601 = sws_getCoefficients(SWS_CS_ITU601);
  // srcRange / dstRange: 0 = limited (16..235 luma), 1 = full. RGB is full range.
  const int srcRange = from == AV_PIX_FMT_RGB24 ? 1 : 0;
  const int dstRange = to == AV_PIX_FMT_RGB24 ? 1 : 0;
  sws_setColorspaceDetails(c.get(), bt601, srcRange, bt601, dstRange, 0, 1 << 16, 1 << 16);
  return c;
}

}  // namespace

YuvPicture rgbToYuv420(const Image& rgb) {
  check(rgb.channels == 3, "rgbToYuv420 needs an RGB image");
  check(rgb.width > 0 && rgb.height > 0 && rgb.width % 2 == 0 && rgb.height % 2 == 0,
        "rgbToYuv420 needs an even, non-empty size");
  YuvPicture out(rgb.width, rgb.height);
  auto c = converter(rgb.width, rgb.height, AV_PIX_FMT_RGB24, AV_PIX_FMT_YUV420P);
  PaddedPlane in(rgb.width * 3, rgb.height);
  in.copyFrom(rgb.pixels.data());
  PaddedPlane y(out.width, out.height), u(out.chromaWidth(), out.chromaHeight()),
      v(out.chromaWidth(), out.chromaHeight());
  const uint8_t* src[1] = {in.data()};
  const int srcStride[1] = {in.stride()};
  uint8_t* dst[3] = {y.data(), u.data(), v.data()};
  const int dstStride[3] = {y.stride(), u.stride(), v.stride()};
  sws_scale(c.get(), src, srcStride, 0, rgb.height, dst, dstStride);
  y.copyTo(out.y.data());
  u.copyTo(out.u.data());
  v.copyTo(out.v.data());
  return out;
}

Image yuv420ToRgb(const YuvPicture& picture) {
  check(picture.width > 0 && picture.height > 0, "yuv420ToRgb needs a picture");
  Image out(picture.width, picture.height, 3);
  auto c = converter(picture.width, picture.height, AV_PIX_FMT_YUV420P, AV_PIX_FMT_RGB24);
  PaddedPlane y(picture.width, picture.height), u(picture.chromaWidth(), picture.chromaHeight()),
      v(picture.chromaWidth(), picture.chromaHeight());
  y.copyFrom(picture.y.data());
  u.copyFrom(picture.u.data());
  v.copyFrom(picture.v.data());
  PaddedPlane rgb(picture.width * 3, picture.height);
  const uint8_t* src[3] = {y.data(), u.data(), v.data()};
  const int srcStride[3] = {y.stride(), u.stride(), v.stride()};
  uint8_t* dst[1] = {rgb.data()};
  const int dstStride[1] = {rgb.stride()};
  sws_scale(c.get(), src, srcStride, 0, picture.height, dst, dstStride);
  rgb.copyTo(out.pixels.data());
  return out;
}

}  // namespace tdvo
