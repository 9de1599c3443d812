#include "decoder/decoder_version.h"

#include <draco/core/draco_version.h>

#include "bitstream/syntax.h"

namespace tdvo {

std::vector<std::string> decoderVersionLines() {
  return {"stream syntax version " + std::to_string(kSyntaxVersion),
          std::string("Draco ") + draco::kDracoVersion};
}

}  // namespace tdvo
