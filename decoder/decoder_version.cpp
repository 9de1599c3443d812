#include "decoder/decoder_version.h"

#include <draco/core/draco_version.h>

#include "bitstream/syntax.h"

namespace tdvo {

std::vector<std::string> decoderVersionLines() {
  // The versions the decoder reads (3dvo-enc writes the newest).
  return {"stream syntax version " + std::to_string(kSyntaxVersion) + " (reads " +
              std::to_string(kMinSyntaxVersion) + " to " + std::to_string(kSyntaxVersion) + ")",
          std::string("Draco ") + draco::kDracoVersion};
}

}  // namespace tdvo
