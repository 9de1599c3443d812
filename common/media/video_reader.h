// Reading camera videos frame by frame through FFmpeg (libavformat, libavcodec, libswscale).
//
// Any container and codec the installed FFmpeg reads; frames come out as 8-bit RGB Images in
// display order. The colour conversion uses the matrix and range the stream declares (BT.601
// limited range when it declares none), with libswscale's bit-exact flags so that the same file
// gives the same pixels on every machine with the same FFmpeg version.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "common/views/image.h"

namespace tdvo {

class VideoReader {
 public:
  // Opens the file and its first video stream. Throws Error naming the file when it cannot be
  // opened, has no video stream or no decoder for it.
  explicit VideoReader(const std::string& path);
  ~VideoReader();
  VideoReader(const VideoReader&) = delete;
  VideoReader& operator=(const VideoReader&) = delete;

  int width() const;
  int height() const;
  // Frames per second: the stream's base frame rate (else its average; 0 when unknown).
  double frameRate() const;
  // The frame count the container declares, or −1 when it does not. Only a hint: containers
  // may count packets that hold no picture (countVideoFrames decodes to be sure).
  int64_t declaredFrameCount() const;

  // Decodes the next frame into `rgb`. Returns false at the end of the stream. Throws Error on a
  // decoding error.
  bool read(Image& rgb);
  // Decodes the next frame without converting it (for counting and seeking forward).
  bool skip();
  // Index of the frame the next read() returns (frames read so far).
  int64_t position() const;

  struct State;  // FFmpeg contexts (defined in the .cpp)

 private:
  std::unique_ptr<State> state_;
};

// Counts the frames of a video by decoding it to the end.
int64_t countVideoFrames(const std::string& path);

}  // namespace tdvo
