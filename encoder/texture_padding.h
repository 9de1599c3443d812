// Texture preprocessing: what the encoder hands to H.264 for one camera and frame.
//
// The picture is the texture box cut out of the camera frame (pixels past the frame's edge are
// mid-grey), converted to YUV 4:2:0 (common/media/yuv.h), then padded outside the object's shape:
//   none         nothing: the background stays;
//   mb128        every macroblock the shape does not touch becomes Y = Cb = Cr = 128 (the
//                source paper's method);
//   extrapolate  as mb128, and inside the macroblocks on the shape's boundary every pixel
//                outside the shape is filled by MPEG-4-style repetitive padding (per row: the
//                mean of the nearest shape pixels to the left and right, or the one that
//                exists; rows still empty then per column the same way), in every plane (a
//                chroma sample counts as inside when any of its 2×2 luma pixels is).
// Padding only changes pixels outside the shape, which the decoder never shows.
#pragma once

#include "common/media/yuv.h"
#include "common/views/image.h"
#include "common/views/texture_shape.h"

namespace tdvo {

enum class TexturePadding { kNone = 0, kMb128 = 1, kExtrapolate = 2 };

// `frame` is the camera's RGB frame, `shape` its object mask (same size).
YuvPicture prepareTexture(const Image& frame, const Image& shape, const TextureBox& box,
                          TexturePadding padding);

}  // namespace tdvo
