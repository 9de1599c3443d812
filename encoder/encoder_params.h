// The encoder's parameters: every cfg key of 3dvo-enc, bound in one option table.
#pragma once

#include <string>

#include "bitstream/syntax.h"
#include "common/config.h"

namespace tdvo {

struct EncoderParams {
  // Input
  std::string inputMeshPattern;
  int firstFrame = 0;
  int frameCount = 1;
  double frameRate = 25.0;
  // Geometry
  int gridBits = 12;
  int gomSize = 1;
  PMeshMode pmeshMode = PMeshMode::kIntra;
  int dracoSpeed = 0;
  // Output
  std::string bitstreamFile;
  std::string reconMeshPattern;

  // Binds every field to its cfg key (the single list of keys; docs/options.md mirrors it).
  void registerOptions(OptionTable& table);
  // Checks what single-key ranges cannot: required keys, patterns. Throws Error.
  void validate() const;
};

}  // namespace tdvo
