// The decoder's view of a texture picture decoder (H.264 access units to YUV 4:2:0 pictures).
//
// The geometry decoder (tdvo_decoder) knows only this interface, so that a program that decodes
// geometry alone links no video library. The texture component (tdvo_texture_decoder:
// decoder/texture/h264_decoder.h, FFmpeg's libavcodec) provides the implementation, given to
// StreamDecoder::setPictureDecoder.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/views/yuv_picture.h"

namespace tdvo {

class PictureDecoder {
 public:
  virtual ~PictureDecoder() = default;
  // Decodes one access unit, which must yield exactly one picture of the given size (3DVO
  // texture streams have no reordering). Throws Error otherwise.
  virtual YuvPicture decode(const std::vector<uint8_t>& accessUnit, int width, int height) = 0;
};

// Makes one camera's decoder; `context` names the stream part in error messages.
using PictureDecoderFactory =
    std::function<std::unique_ptr<PictureDecoder>(const std::string& context)>;

}  // namespace tdvo
