#include "common/media/video_reader.h"

#include <cstdio>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libswscale/swscale.h>
}

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/media/ffmpeg_log.h"
#include "common/media/padded_plane.h"

namespace tdvo {

namespace {

std::string avError(int code) {
  char buffer[AV_ERROR_MAX_STRING_SIZE] = {0};
  av_strerror(code, buffer, sizeof buffer);
  return buffer;
}

int swsColourSpace(AVColorSpace space) {
  switch (space) {
    case AVCOL_SPC_BT709:
      return SWS_CS_ITU709;
    case AVCOL_SPC_FCC:
      return SWS_CS_FCC;
    case AVCOL_SPC_SMPTE240M:
      return SWS_CS_SMPTE240M;
    case AVCOL_SPC_BT2020_NCL:
    case AVCOL_SPC_BT2020_CL:
      return SWS_CS_BT2020;
    default:
      return SWS_CS_ITU601;  // also for unspecified: standard definition video
  }
}

bool isFullRangeFormat(int format) {
  return format == AV_PIX_FMT_YUVJ420P || format == AV_PIX_FMT_YUVJ422P ||
         format == AV_PIX_FMT_YUVJ444P || format == AV_PIX_FMT_YUVJ440P;
}

}  // namespace

struct VideoReader::State {
  std::string path;
  AVFormatContext* format = nullptr;
  AVCodecContext* decoder = nullptr;
  AVPacket* packet = nullptr;
  AVFrame* frame = nullptr;
  SwsContext* scaler = nullptr;
  int stream = -1;
  bool flushing = false, ended = false;
  int64_t position = 0;
  int damagedFrames = 0;  // frames FFmpeg reported errors for (and concealed)

  ~State() {
    sws_freeContext(scaler);
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&decoder);
    avformat_close_input(&format);
  }
};

VideoReader::VideoReader(const std::string& path) : state_(std::make_unique<State>()) {
  // FFmpeg's warnings about harmless stream quirks would clutter every app's stderr, and its
  // error lines would come before the app's own: they are routed away (common/media/ffmpeg_log.h);
  // errors are reported through exceptions.
  routeFfmpegLog();
  State& s = *state_;
  s.path = path;
  noteFileRead(path);
  int ret = avformat_open_input(&s.format, path.c_str(), nullptr, nullptr);
  if (ret < 0) throw Error(path + ": cannot open video: " + avError(ret));
  ret = avformat_find_stream_info(s.format, nullptr);
  if (ret < 0) throw Error(path + ": cannot read stream information: " + avError(ret));
  const AVCodec* codec = nullptr;
  s.stream = av_find_best_stream(s.format, AVMEDIA_TYPE_VIDEO, -1, -1, &codec, 0);
  if (s.stream < 0) throw Error(path + ": no video stream");
  check(codec != nullptr, path + ": no decoder for the video stream's codec");
  s.decoder = avcodec_alloc_context3(codec);
  check(s.decoder != nullptr, path + ": cannot allocate a decoder");
  ret = avcodec_parameters_to_context(s.decoder, s.format->streams[s.stream]->codecpar);
  if (ret < 0) throw Error(path + ": bad codec parameters: " + avError(ret));
  s.decoder->thread_count = 1;  // one thread: frames come out the same way on every machine
  ret = avcodec_open2(s.decoder, codec, nullptr);
  if (ret < 0) throw Error(path + ": cannot open the decoder: " + avError(ret));
  check(s.decoder->width > 0 && s.decoder->height > 0 && s.decoder->width <= (1 << 15) &&
            s.decoder->height <= (1 << 15),
        path + ": invalid video size " + std::to_string(s.decoder->width) + "x" +
            std::to_string(s.decoder->height));
  s.packet = av_packet_alloc();
  s.frame = av_frame_alloc();
  check(s.packet && s.frame, path + ": out of memory");
}

VideoReader::~VideoReader() = default;

int VideoReader::width() const {
  return state_->decoder->width;
}

int VideoReader::height() const {
  return state_->decoder->height;
}

double VideoReader::frameRate() const {
  // The base rate first: the average counts the empty packets of "packed B-frames" MPEG-4 AVIs.
  const AVStream* stream = state_->format->streams[state_->stream];
  for (const AVRational r : {stream->r_frame_rate, stream->avg_frame_rate})
    if (r.num > 0 && r.den > 0) return av_q2d(r);
  return 0.0;
}

int64_t VideoReader::declaredFrameCount() const {
  const int64_t n = state_->format->streams[state_->stream]->nb_frames;
  return n > 0 ? n : -1;
}

int64_t VideoReader::position() const {
  return state_->position;
}

namespace {

// Decodes the next frame into s.frame; false at the end of the stream.
bool decodeNext(VideoReader::State& s) {
  if (s.ended) return false;
  const std::string where = s.path + ": frame " + std::to_string(s.position);
  for (;;) {
    int ret = avcodec_receive_frame(s.decoder, s.frame);
    if (ret == 0) {
      // An input video is taken as FFmpeg decodes it, concealment included, but not silently:
      // FFmpeg's own lines are routed away (common/media/ffmpeg_log.h), so the first few damaged
      // frames are named here.
      const std::string message = takeFfmpegError();
      if (!message.empty() && ++s.damagedFrames <= 3)
        std::fprintf(stderr, "warning: %s: FFmpeg reports '%s'; the frame is used as concealed%s\n",
                     where.c_str(), message.c_str(),
                     s.damagedFrames == 3 ? " (further such warnings for this video omitted)" : "");
      return true;
    }
    if (ret == AVERROR_EOF) {
      s.ended = true;
      return false;
    }
    if (ret != AVERROR(EAGAIN)) throw Error(where + ": decoding error: " + avError(ret));
    if (s.flushing) {
      s.ended = true;
      return false;
    }
    ret = av_read_frame(s.format, s.packet);
    if (ret < 0) {
      // End of file (or an unreadable tail): drain the frames the decoder still holds.
      s.flushing = true;
      ret = avcodec_send_packet(s.decoder, nullptr);
      if (ret < 0 && ret != AVERROR_EOF) throw Error(where + ": decoding error: " + avError(ret));
      continue;
    }
    if (s.packet->stream_index == s.stream) {
      ret = avcodec_send_packet(s.decoder, s.packet);
      if (ret < 0 && ret != AVERROR(EAGAIN) && ret != AVERROR_INVALIDDATA) {
        av_packet_unref(s.packet);
        throw Error(where + ": decoding error: " + avError(ret));
      }
    }
    av_packet_unref(s.packet);
  }
}

}  // namespace

bool VideoReader::skip() {
  if (!decodeNext(*state_)) return false;
  av_frame_unref(state_->frame);
  ++state_->position;
  return true;
}

bool VideoReader::read(Image& rgb) {
  State& s = *state_;
  if (!decodeNext(s)) return false;
  const std::string where = s.path + ": frame " + std::to_string(s.position);
  const int w = s.frame->width, h = s.frame->height;
  if (w != s.decoder->width || h != s.decoder->height) {
    av_frame_unref(s.frame);
    throw Error(where + ": frame size changes within the video (" + std::to_string(w) + "x" +
                std::to_string(h) + ")");
  }
  s.scaler = sws_getCachedContext(s.scaler, w, h, static_cast<AVPixelFormat>(s.frame->format), w, h,
                                  AV_PIX_FMT_RGB24, SWS_BILINEAR | SWS_ACCURATE_RND | SWS_BITEXACT,
                                  nullptr, nullptr, nullptr);
  if (!s.scaler) {
    av_frame_unref(s.frame);
    throw Error(where + ": cannot convert pixel format " + std::to_string(s.frame->format) +
                " to RGB");
  }
  const int fullRange =
      (s.frame->color_range == AVCOL_RANGE_JPEG || isFullRangeFormat(s.frame->format)) ? 1 : 0;
  sws_setColorspaceDetails(s.scaler, sws_getCoefficients(swsColourSpace(s.frame->colorspace)),
                           fullRange, sws_getCoefficients(SWS_CS_DEFAULT), 1, 0, 1 << 16, 1 << 16);
  rgb = Image(w, h, 3);
  PaddedPlane converted(3 * w, h);  // not rgb's packed rows: libswscale writes past a row's end
  uint8_t* destination[4] = {converted.data(), nullptr, nullptr, nullptr};
  int strides[4] = {converted.stride(), 0, 0, 0};
  sws_scale(s.scaler, s.frame->data, s.frame->linesize, 0, h, destination, strides);
  converted.copyTo(rgb.pixels.data());
  av_frame_unref(s.frame);
  ++s.position;
  return true;
}

int64_t countVideoFrames(const std::string& path) {
  VideoReader reader(path);
  while (reader.skip()) {
  }
  return reader.position();
}

}  // namespace tdvo
