#include "common/views/yuv_picture.h"

namespace tdvo {

YuvPicture::YuvPicture(int w, int h, uint8_t fill)
    : width(w),
      height(h),
      y(static_cast<size_t>(w) * h, fill),
      u(static_cast<size_t>(w / 2) * (h / 2), fill),
      v(static_cast<size_t>(w / 2) * (h / 2), fill) {}

Md5Digest pictureDigest(const YuvPicture& picture) {
  Md5 md5;
  md5.update(picture.y.data(), picture.y.size());
  md5.update(picture.u.data(), picture.u.size());
  md5.update(picture.v.data(), picture.v.size());
  return md5.finish();
}

std::string textureHashLine(int frame, int camera, const YuvPicture& picture) {
  return "MD5 frame=" + std::to_string(frame) + " texture cam=" + std::to_string(camera) + " " +
         toHex(pictureDigest(picture));
}

}  // namespace tdvo
