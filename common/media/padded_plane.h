// A picture plane laid out as FFmpeg's libswscale needs it (yuv.cpp, video_reader.cpp).
#pragma once

extern "C" {
#include <libavutil/mem.h>
}

#include <cstdint>
#include <cstring>
#include <string>

#include "common/core/error.h"

namespace tdvo {

// A plane as libswscale needs it: its SIMD code loads and stores whole vectors, past the end
// of a row (up to its alignment) and of the last row, so rows are padded to a multiple of 64
// bytes plus 64, two rows more are allocated, and the start is 64-byte aligned (av_malloc).
// Tightly packed planes (std::vector) were read and written out of bounds: a heap overflow
// and abort at 4 x 5 pixels, invalid reads at 322 x 242 (valgrind).
class PaddedPlane {
 public:
  PaddedPlane(int rowBytes, int rows)
      : rowBytes_(rowBytes), stride_((rowBytes + 63) / 64 * 64 + 64), rows_(rows) {
    data_ = static_cast<uint8_t*>(av_mallocz(size_t(stride_) * size_t(rows + 2)));
    if (!data_)
      throw Error("libswscale: out of memory for a " + std::to_string(rows) + "-row plane");
  }
  ~PaddedPlane() { av_free(data_); }
  PaddedPlane(const PaddedPlane&) = delete;
  PaddedPlane& operator=(const PaddedPlane&) = delete;
  uint8_t* data() { return data_; }
  int stride() const { return stride_; }
  void copyFrom(const uint8_t* packed) {
    for (int r = 0; r < rows_; ++r)
      std::memcpy(data_ + size_t(r) * size_t(stride_), packed + size_t(r) * size_t(rowBytes_),
                  size_t(rowBytes_));
  }
  void copyTo(uint8_t* packed) const {
    for (int r = 0; r < rows_; ++r)
      std::memcpy(packed + size_t(r) * size_t(rowBytes_), data_ + size_t(r) * size_t(stride_),
                  size_t(rowBytes_));
  }

 private:
  int rowBytes_, stride_, rows_;
  uint8_t* data_;
};

}  // namespace tdvo
