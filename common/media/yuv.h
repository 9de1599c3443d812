// YUV 4:2:0 pictures: what the texture coder codes. Conversion from and to RGB goes through
// FFmpeg's libswscale with a fixed, documented set-up (docs/textures.md): ITU-R BT.601
// coefficients, limited ("TV") range, chroma sited at the centre of each 2×2 luma block,
// bit-exact mode. The MD5 of a decoded picture covers its planes, not any RGB conversion.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/views/image.h"
#include "common/views/yuv_picture.h"

namespace tdvo {

// RGB (3 channels) to YUV 4:2:0; the image's width and height must be even.
YuvPicture rgbToYuv420(const Image& rgb);
// YUV 4:2:0 to RGB (3 channels).
Image yuv420ToRgb(const YuvPicture& picture);

}  // namespace tdvo
