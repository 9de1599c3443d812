#include "tools/render/mp4_writer.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
}

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/number_text.h"
#include "common/media/ffmpeg_log.h"
#include "common/media/yuv.h"

namespace tdvo {

namespace {

std::string avError(int code) {
  char buffer[AV_ERROR_MAX_STRING_SIZE] = {0};
  av_strerror(code, buffer, sizeof buffer);
  return buffer;
}

}  // namespace

struct Mp4Writer::State {
  std::string path, partial;
  StagedFiles staged;  // the partial file: created exclusively, put in place by file()'s commit
  int width = 0, height = 0;            // of the frames given
  int codedWidth = 0, codedHeight = 0;  // rounded up to even
  AVFormatContext* format = nullptr;
  AVCodecContext* encoder = nullptr;
  AVStream* stream = nullptr;
  AVPacket* packet = nullptr;
  AVFrame* frame = nullptr;
  int64_t next = 0;
  bool open = false;

  ~State() {
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&encoder);
    if (format) {
      if (open) avio_closep(&format->pb);
      avformat_free_context(format);
    }
  }

  // Sends a frame (or nullptr to flush) and writes every packet the encoder returns.
  void encode(AVFrame* input) {
    int r = avcodec_send_frame(encoder, input);
    check(r >= 0, path + ": encoding failed: " + avError(r));
    for (;;) {
      r = avcodec_receive_packet(encoder, packet);
      if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return;
      check(r >= 0, path + ": encoding failed: " + avError(r));
      // Every frame lasts one frame period; without a duration the muxer's edit list would end
      // at the last frame's start and players would drop it.
      if (packet->duration == 0) packet->duration = 1;
      av_packet_rescale_ts(packet, encoder->time_base, stream->time_base);
      packet->stream_index = stream->index;
      r = av_interleaved_write_frame(format, packet);
      check(r >= 0, path + ": writing failed: " + avError(r));
    }
  }
};

void checkMp4FrameRate(double frameRate, const std::string& path) {
  check(std::isfinite(frameRate) && frameRate >= 0.001 && frameRate <= 1000,
        path + ": the frame rate " + formatDouble(frameRate) +
            " (the dataset's frames.rate) is outside what an MP4 is written at, 0.001 to 1000 "
            "frames per second");
}

Mp4Writer::Mp4Writer(const std::string& path, int width, int height, double frameRate, int crf)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.path = path;
  s.width = width, s.height = height;
  s.codedWidth = width + (width & 1), s.codedHeight = height + (height & 1);
  check(width > 0 && height > 0, path + ": empty frame size");
  checkMp4FrameRate(frameRate, path);
  check(crf >= 0 && crf <= 51, path + ": the CRF must be in 0..51");
  s.partial = s.staged.stage(path);
  // x264 reports its settings and statistics at the info level, and errors come through
  // exceptions: FFmpeg's own lines are routed away (common/media/ffmpeg_log.h).
  routeFfmpegLog();
  int r = avformat_alloc_output_context2(&s.format, nullptr, "mp4", s.partial.c_str());
  check(r >= 0 && s.format, path + ": cannot set up an MP4 file: " + avError(r));
  const AVCodec* codec = avcodec_find_encoder_by_name("libx264");
  check(codec != nullptr, "the installed FFmpeg has no libx264 encoder");
  s.stream = avformat_new_stream(s.format, nullptr);
  s.encoder = avcodec_alloc_context3(codec);
  s.packet = av_packet_alloc();
  s.frame = av_frame_alloc();
  check(s.stream && s.encoder && s.packet && s.frame, "out of memory");
  s.encoder->width = s.codedWidth;
  s.encoder->height = s.codedHeight;
  s.encoder->pix_fmt = AV_PIX_FMT_YUV420P;
  // Frame rate as a rational with millisecond-ish precision (25 → 25/1, 29.97 → 2997/100).
  const AVRational rate = av_d2q(frameRate, 100000);
  s.encoder->time_base = av_inv_q(rate);
  s.encoder->framerate = rate;
  s.encoder->color_range = AVCOL_RANGE_MPEG;
  s.encoder->colorspace = AVCOL_SPC_SMPTE170M;  // BT.601
  s.encoder->color_primaries = AVCOL_PRI_SMPTE170M;
  s.encoder->color_trc = AVCOL_TRC_SMPTE170M;
  if (s.format->oformat->flags & AVFMT_GLOBALHEADER)
    s.encoder->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  av_opt_set(s.encoder->priv_data, "preset", "medium", 0);
  av_opt_set(s.encoder->priv_data, "crf", std::to_string(crf).c_str(), 0);
  r = avcodec_open2(s.encoder, codec, nullptr);
  check(r >= 0, path + ": cannot open the libx264 encoder: " + avError(r));
  r = avcodec_parameters_from_context(s.stream->codecpar, s.encoder);
  check(r >= 0, path + ": " + avError(r));
  s.stream->time_base = s.encoder->time_base;
  r = avio_open(&s.format->pb, s.partial.c_str(), AVIO_FLAG_WRITE);
  check(r >= 0, s.partial + ": cannot open for writing: " + avError(r));
  s.open = true;
  r = avformat_write_header(s.format, nullptr);
  check(r >= 0, path + ": cannot write the MP4 header: " + avError(r));
  s.frame->format = AV_PIX_FMT_YUV420P;
  s.frame->width = s.codedWidth;
  s.frame->height = s.codedHeight;
  r = av_frame_get_buffer(s.frame, 0);
  check(r >= 0, "out of memory");
}

Mp4Writer::~Mp4Writer() = default;

void Mp4Writer::write(const Image& image) {
  State& s = *state_;
  check(s.open, s.path + ": write after close");
  check(image.width == s.width && image.height == s.height,
        s.path + ": frame size differs from the first frame");
  // RGB at the coded (even) size, repeating the last column / row.
  Image rgb(s.codedWidth, s.codedHeight, 3);
  for (int y = 0; y < s.codedHeight; ++y)
    for (int x = 0; x < s.codedWidth; ++x)
      for (int c = 0; c < 3; ++c)
        rgb.at(x, y, c) = image.at(std::min(x, s.width - 1), std::min(y, s.height - 1),
                                   image.channels >= 3 ? c : 0);
  const YuvPicture yuv = rgbToYuv420(rgb);
  const int r = av_frame_make_writable(s.frame);
  check(r >= 0, "out of memory");
  const uint8_t* planes[3] = {yuv.y.data(), yuv.u.data(), yuv.v.data()};
  const int widths[3] = {yuv.width, yuv.chromaWidth(), yuv.chromaWidth()};
  const int heights[3] = {yuv.height, yuv.chromaHeight(), yuv.chromaHeight()};
  for (int p = 0; p < 3; ++p)
    for (int y = 0; y < heights[p]; ++y)
      std::copy(planes[p] + static_cast<size_t>(y) * static_cast<size_t>(widths[p]),
                planes[p] + static_cast<size_t>(y + 1) * static_cast<size_t>(widths[p]),
                s.frame->data[p] + static_cast<ptrdiff_t>(y) * s.frame->linesize[p]);
  s.frame->pts = s.next++;
  s.encode(s.frame);
}

void Mp4Writer::close() {
  State& s = *state_;
  if (!s.open) return;
  s.encode(nullptr);
  int r = av_write_trailer(s.format);
  check(r >= 0, s.path + ": cannot finish the MP4: " + avError(r));
  r = avio_closep(&s.format->pb);
  s.open = false;
  check(r >= 0, s.path + ": closing failed: " + avError(r));
}

StagedFiles& Mp4Writer::file() {
  return state_->staged;
}

}  // namespace tdvo
