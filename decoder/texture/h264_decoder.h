// H.264 decoding of one camera's texture access units through FFmpeg's libavcodec: the texture
// component (tdvo_texture_decoder) of the decoder.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "decoder/picture_decoder.h"

struct AVCodecContext;
struct AVPacket;
struct AVFrame;

namespace tdvo {

class H264Decoder : public PictureDecoder {
 public:
  // `context` names the stream part in error messages.
  explicit H264Decoder(std::string context);
  ~H264Decoder() override;
  H264Decoder(const H264Decoder&) = delete;
  H264Decoder& operator=(const H264Decoder&) = delete;

  // Decodes one access unit, which must yield exactly one picture of the given size (3DVO
  // texture streams have no reordering). Throws Error otherwise.
  YuvPicture decode(const std::vector<uint8_t>& accessUnit, int width, int height) override;

 private:
  AVCodecContext* codec_ = nullptr;
  AVPacket* packet_ = nullptr;
  AVFrame* frame_ = nullptr;
  std::string context_;
};

// The factory StreamDecoder::setPictureDecoder takes: an H264Decoder.
std::unique_ptr<PictureDecoder> makeH264Decoder(const std::string& context);

}  // namespace tdvo
