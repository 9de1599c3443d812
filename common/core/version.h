// What `--version` prints: the 3DVO release and the versions of the libraries an app links.
#pragma once

#include <string>
#include <vector>

namespace tdvo {

// The 3DVO release (the CMake project version), e.g. "0.1.0".
const char* releaseVersion();

// One line per library of the core layer (tdvo_core) that can say its version: zlib, with the
// version it was built against and the one loaded at run time. Apps add the lines of the other
// layers they link (OptionTable::addVersionLines; e.g. mediaLibraryVersions()).
std::vector<std::string> coreLibraryVersions();

// "V" if the two agree, else "V (built against), W (loaded)".
std::string builtAndLoaded(const std::string& built, const std::string& loaded);

}  // namespace tdvo
