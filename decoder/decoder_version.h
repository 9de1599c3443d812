// The --version lines of apps that link the decoder library: the stream syntax version it reads
// and writes, and the Draco release it links.
#pragma once

#include <string>
#include <vector>

namespace tdvo {

std::vector<std::string> decoderVersionLines();

}  // namespace tdvo
