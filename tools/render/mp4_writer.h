// Writing rendered frames as an H.264 MP4 through FFmpeg (libavformat's mp4 muxer, libavcodec's
// libx264 encoder), for viewing free-viewpoint output in any player.
//
// Frames are converted to YUV 4:2:0 with common/media/yuv.h (BT.601, limited range, tagged as such
// in the stream). 4:2:0 needs an even size: an odd width or height gets one more column or row, a
// copy of the last one. The file is written under a temporary name and renamed by finish(), so a
// failed run leaves no half-written MP4.
#pragma once

#include <memory>
#include <string>

#include "common/core/file_io.h"
#include "common/views/image.h"

namespace tdvo {

// The frame rates an MP4 is written at: 0.001 to 1000 frames per second (the rate becomes a
// fraction with a denominator of at most 100000). Throws Error naming `path` otherwise.
void checkMp4FrameRate(double frameRate, const std::string& path);

class Mp4Writer {
 public:
  // `crf`: x264's constant rate factor (0 lossless … 51; 18 looks transparent).
  Mp4Writer(const std::string& path, int width, int height, double frameRate, int crf);
  ~Mp4Writer();
  Mp4Writer(const Mp4Writer&) = delete;
  Mp4Writer& operator=(const Mp4Writer&) = delete;

  // Appends one RGB or RGBA frame (alpha dropped) of the size given at construction.
  void write(const Image& frame);
  // Flushes the encoder and closes the (staged) file: every error of writing it happens here.
  void close();
  // The staged file, to be put in place with the run's other outputs after close()
  // (commitAll, common/core/file_io.h: a run that fails leaves the previous file and folders).
  StagedFiles& file();

  struct State;  // FFmpeg contexts (defined in the .cpp)

 private:
  std::unique_ptr<State> state_;
};

}  // namespace tdvo
