// H.264 decoding of one camera's texture access units through FFmpeg's libavcodec.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/media/yuv.h"

struct AVCodecContext;
struct AVPacket;
struct AVFrame;

namespace tdvo {

class H264Decoder {
 public:
  // `context` names the stream part in error messages.
  explicit H264Decoder(std::string context);
  ~H264Decoder();
  H264Decoder(const H264Decoder&) = delete;
  H264Decoder& operator=(const H264Decoder&) = delete;

  // Decodes one access unit, which must yield exactly one picture of the given size (3DVO
  // texture streams have no reordering). Throws Error otherwise.
  YuvPicture decode(const std::vector<uint8_t>& accessUnit, int width, int height);

 private:
  AVCodecContext* codec_ = nullptr;
  AVPacket* packet_ = nullptr;
  AVFrame* frame_ = nullptr;
  std::string context_;
};

}  // namespace tdvo
