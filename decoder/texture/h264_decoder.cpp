#include "decoder/texture/h264_decoder.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/imgutils.h>
}

#include <cstring>

#include "common/core/error.h"
#include "common/media/ffmpeg_log.h"

namespace tdvo {

H264Decoder::H264Decoder(std::string context) : context_(std::move(context)) {
  const AVCodec* codec = avcodec_find_decoder(AV_CODEC_ID_H264);
  if (!codec) throw Error("FFmpeg has no H.264 decoder");
  codec_ = avcodec_alloc_context3(codec);
  packet_ = av_packet_alloc();
  frame_ = av_frame_alloc();
  if (!codec_ || !packet_ || !frame_) throw Error("FFmpeg: out of memory");
  // One thread and low delay: each access unit comes out as its picture at once.
  codec_->thread_count = 1;
  codec_->flags |= AV_CODEC_FLAG_LOW_DELAY;
  // Damaged texture data is an error, never concealed: FFmpeg stops at the first error it
  // recognises (and checks what it can), conceals nothing, and every error it logs while decoding
  // an access unit, or any error flag on the picture, fails that unit (decode()).
  codec_->err_recognition = AV_EF_EXPLODE | AV_EF_CRCCHECK | AV_EF_BITSTREAM | AV_EF_BUFFER |
                            AV_EF_CAREFUL | AV_EF_COMPLIANT | AV_EF_AGGRESSIVE;
  codec_->error_concealment = 0;
  routeFfmpegLog();
  if (avcodec_open2(codec_, codec, nullptr) < 0) throw Error("FFmpeg cannot open H.264 decoder");
}

H264Decoder::~H264Decoder() {
  av_frame_free(&frame_);
  av_packet_free(&packet_);
  avcodec_free_context(&codec_);
}

YuvPicture H264Decoder::decode(const std::vector<uint8_t>& accessUnit, int width, int height) {
  check(!accessUnit.empty(), context_ + ": empty H.264 access unit");
  av_packet_unref(packet_);
  if (av_new_packet(packet_, static_cast<int>(accessUnit.size())) < 0)
    throw Error("FFmpeg: out of memory");
  std::memcpy(packet_->data, accessUnit.data(), accessUnit.size());
  // FFmpeg sizes its pictures and tables from the access unit's SPS, which may declare far more
  // than the texture box: a picture larger than the box is refused before FFmpeg allocates it
  // (with room for FFmpeg's alignment of its buffers: 96 x 80 pictures are checked as 128 x 80).
  codec_->max_pixels = (static_cast<int64_t>(width) + 128) * (static_cast<int64_t>(height) + 128);
  takeFfmpegError();  // a message from before this unit is not about it
  // FFmpeg's first error message, if any, says what it found.
  auto detail = []() {
    const std::string message = takeFfmpegError();
    return message.empty() ? std::string() : " (FFmpeg: " + message + ")";
  };
  if (avcodec_send_packet(codec_, packet_) < 0)
    throw Error(context_ + ": damaged H.264 access unit: the decoder rejects it" + detail());
  const int got = avcodec_receive_frame(codec_, frame_);
  if (got < 0)
    throw Error(context_ + ": damaged H.264 access unit: it gives no picture" + detail());
  const std::string logged = detail();
  if (frame_->decode_error_flags != 0 || (frame_->flags & AV_FRAME_FLAG_CORRUPT) ||
      !logged.empty()) {
    av_frame_unref(frame_);
    throw Error(context_ + ": damaged H.264 access unit" +
                (logged.empty() ? std::string(" (FFmpeg flags the picture as corrupt)") : logged));
  }
  if (frame_->format != AV_PIX_FMT_YUV420P || frame_->width != width || frame_->height != height)
    throw Error(context_ + ": H.264 picture is " + std::to_string(frame_->width) + "x" +
                std::to_string(frame_->height) + " (format " + std::to_string(frame_->format) +
                "), expected " + std::to_string(width) + "x" + std::to_string(height) + " 4:2:0");
  YuvPicture out(width, height);
  auto copyPlane = [&](int plane, std::vector<uint8_t>& dst, int w, int h) {
    for (int row = 0; row < h; ++row)
      std::memcpy(dst.data() + static_cast<size_t>(row) * w,
                  frame_->data[plane] + static_cast<ptrdiff_t>(row) * frame_->linesize[plane], w);
  };
  copyPlane(0, out.y, width, height);
  copyPlane(1, out.u, width / 2, height / 2);
  copyPlane(2, out.v, width / 2, height / 2);
  av_frame_unref(frame_);
  return out;
}

std::unique_ptr<PictureDecoder> makeH264Decoder(const std::string& context) {
  return std::make_unique<H264Decoder>(context);
}

}  // namespace tdvo
