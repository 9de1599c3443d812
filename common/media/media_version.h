// What `--version` prints for the media layer (tdvo_media): libpng and the FFmpeg libraries.
#pragma once

#include <string>
#include <vector>

namespace tdvo {

// One line per library, with the version it was built against and the one loaded at run time.
std::vector<std::string> mediaLibraryVersions();

}  // namespace tdvo
