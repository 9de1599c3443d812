#include "common/media/media_version.h"

#include <png.h>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/avutil.h>
#include <libswscale/swscale.h>
}

#include "common/core/version.h"

namespace tdvo {

namespace {

std::string ffmpegVersion(unsigned runtime) {
  return std::to_string(AV_VERSION_MAJOR(runtime)) + "." +
         std::to_string(AV_VERSION_MINOR(runtime)) + "." +
         std::to_string(AV_VERSION_MICRO(runtime));
}

}  // namespace

std::vector<std::string> mediaLibraryVersions() {
  std::vector<std::string> lines;
  lines.push_back("libpng " + builtAndLoaded(PNG_LIBPNG_VER_STRING, png_get_libpng_ver(nullptr)));
  lines.push_back("FFmpeg libavformat " + builtAndLoaded(AV_STRINGIFY(LIBAVFORMAT_VERSION),
                                                         ffmpegVersion(avformat_version())));
  lines.push_back("FFmpeg libavcodec " + builtAndLoaded(AV_STRINGIFY(LIBAVCODEC_VERSION),
                                                        ffmpegVersion(avcodec_version())));
  lines.push_back("FFmpeg libavutil " +
                  builtAndLoaded(AV_STRINGIFY(LIBAVUTIL_VERSION), ffmpegVersion(avutil_version())));
  lines.push_back("FFmpeg libswscale " + builtAndLoaded(AV_STRINGIFY(LIBSWSCALE_VERSION),
                                                        ffmpegVersion(swscale_version())));
  return lines;
}

}  // namespace tdvo
