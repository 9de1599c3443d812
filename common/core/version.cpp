#include "common/core/version.h"

#include <zlib.h>

#ifndef TDVO_RELEASE_VERSION
#define TDVO_RELEASE_VERSION "unknown"
#endif

namespace tdvo {

std::string builtAndLoaded(const std::string& built, const std::string& loaded) {
  return built == loaded ? built : built + " (built against), " + loaded + " (loaded)";
}

const char* releaseVersion() {
  return TDVO_RELEASE_VERSION;
}

std::vector<std::string> coreLibraryVersions() {
  std::vector<std::string> lines;
  lines.push_back("zlib " + builtAndLoaded(ZLIB_VERSION, zlibVersion()));
  return lines;
}

}  // namespace tdvo
