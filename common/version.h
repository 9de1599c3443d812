// What `--version` prints: the 3DVO release and the versions of the libraries an app links.
#pragma once

#include <string>
#include <vector>

namespace tdvo {

// The 3DVO release (the CMake project version), e.g. "0.1.0".
const char* releaseVersion();

// One line per library every app links through tdvo_common: zlib, libpng and the FFmpeg
// libraries, each with the version it was built against and, where the library can say, the
// version loaded at run time.
std::vector<std::string> coreLibraryVersions();

}  // namespace tdvo
