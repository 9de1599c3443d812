#include "encoder/h264_encoder.h"

#include <x264.h>

#include <cstring>

#include "common/core/error.h"

namespace tdvo {

H264Encoder::H264Encoder(const H264Settings& s) : settings_(s) {
  check(s.width > 0 && s.height > 0 && s.width % 2 == 0 && s.height % 2 == 0,
        "H.264 texture size must be even and non-empty");
  x264_param_t p;
  if (x264_param_default_preset(&p, s.preset.c_str(), nullptr) < 0)
    throw Error("TexturePreset: x264 has no preset '" + s.preset + "'");
  p.i_log_level = X264_LOG_NONE;
  p.i_csp = X264_CSP_I420;
  p.i_width = s.width;
  p.i_height = s.height;
  // Determinism and one access unit per picture, immediately.
  p.i_threads = 1;
  p.b_sliced_threads = 0;
  p.b_deterministic = 1;
  p.i_bframe = 0;
  p.rc.i_lookahead = 0;
  p.i_sync_lookahead = 0;
  p.rc.b_mb_tree = 0;
  p.i_scenecut_threshold = 0;
  p.i_keyint_max = X264_KEYINT_MAX_INFINITE;
  p.b_repeat_headers = 1;
  p.b_annexb = 1;
  p.b_vfr_input = 0;
  // Frame rate as a rational with millisecond precision (only affects rate control).
  p.i_fps_num = static_cast<uint32_t>(s.frameRate * 1000 + 0.5);
  p.i_fps_den = 1000;
  if (s.bitrateKbps > 0) {
    p.rc.i_rc_method = X264_RC_ABR;
    p.rc.i_bitrate = s.bitrateKbps;
  } else {
    p.rc.i_rc_method = X264_RC_CQP;
    p.rc.i_qp_constant = s.qp;
  }
  if (x264_param_apply_profile(&p, "high") < 0) throw Error("x264 rejects the High profile");
  encoder_ = x264_encoder_open(&p);
  if (!encoder_)
    throw Error("x264 cannot open an encoder for " + std::to_string(s.width) + "x" +
                std::to_string(s.height) + " textures");
}

H264Encoder::~H264Encoder() {
  if (encoder_) x264_encoder_close(encoder_);
}

std::vector<uint8_t> H264Encoder::encode(const YuvPicture& picture, bool idr) {
  check(picture.width == settings_.width && picture.height == settings_.height,
        "texture picture size differs from the H.264 encoder's");
  x264_picture_t in, out;
  x264_picture_init(&in);
  in.img.i_csp = X264_CSP_I420;
  in.img.i_plane = 3;
  // x264 only reads the input planes.
  in.img.plane[0] = const_cast<uint8_t*>(picture.y.data());
  in.img.plane[1] = const_cast<uint8_t*>(picture.u.data());
  in.img.plane[2] = const_cast<uint8_t*>(picture.v.data());
  in.img.i_stride[0] = picture.width;
  in.img.i_stride[1] = picture.chromaWidth();
  in.img.i_stride[2] = picture.chromaWidth();
  in.i_pts = pts_++;
  in.i_type = idr ? X264_TYPE_IDR : X264_TYPE_AUTO;
  x264_nal_t* nals = nullptr;
  int numNals = 0;
  const int size = x264_encoder_encode(encoder_, &nals, &numNals, &in, &out);
  if (size < 0) throw Error("x264 failed to encode a texture picture");
  if (size == 0) throw std::logic_error("x264 delayed a picture despite the zero-latency set-up");
  // The payloads of one call are contiguous in memory.
  return std::vector<uint8_t>(nals[0].p_payload, nals[0].p_payload + size);
}

}  // namespace tdvo
