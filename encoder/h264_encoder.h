// H.264 encoding of one camera's texture pictures through the libx264 API.
//
// Set-up for a reference codec: deterministic output (one thread, no scene-cut decisions, no
// B frames, no lookahead, so every input picture yields exactly one access unit at once), Annex
// B byte stream with SPS/PPS repeated at every IDR, an IDR whenever the caller asks for one
// (the encoder asks at every GOM start, which keeps GOMs random-access points), and either a
// constant QP or an average bitrate.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/media/yuv.h"

struct x264_t;

namespace tdvo {

struct H264Settings {
  int width = 0, height = 0;  // multiples of 16 (the texture box)
  double frameRate = 25;
  int qp = 28;          // constant QP (0..51) when bitrateKbps == 0
  int bitrateKbps = 0;  // > 0: average bitrate instead of constant QP
  std::string preset = "medium";
};

class H264Encoder {
 public:
  explicit H264Encoder(const H264Settings& settings);
  ~H264Encoder();
  H264Encoder(const H264Encoder&) = delete;
  H264Encoder& operator=(const H264Encoder&) = delete;

  // Codes one picture (of the settings' size); returns its access unit (Annex B NAL units).
  std::vector<uint8_t> encode(const YuvPicture& picture, bool idr);

 private:
  x264_t* encoder_ = nullptr;
  H264Settings settings_;
  int64_t pts_ = 0;
};

}  // namespace tdvo
