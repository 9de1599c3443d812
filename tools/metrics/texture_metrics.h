// The texture mode of 3dvo-metrics: object PSNR between an original dataset's camera frames and
// a decoded dataset (3dvo-dec output), per camera and frame, and over the sequence.
// Definitions: docs/metrics.md, "Texture metrics".
#pragma once

#include <string>

namespace tdvo {

struct TextureMetricsParams {
  std::string referenceDataset;  // the original: folder or dataset.json
  std::string testDataset;       // the decoded output: folder or dataset.json (RGBA, alpha = shape)
  std::string bitstream;         // optional: the stream decoded, for its texture boxes
  std::string csvFile;           // optional CSV output
  int referenceFirstFrame = 0;   // frame index of the reference compared with test frame
  int testFirstFrame = 0;        // ... this one
  int frameCount = 0;            // 0: as many as both datasets have from the first frames
};

// Runs the comparison, prints the text report on stdout, writes the CSV; throws Error on bad
// input. Returns the exit code (0).
int runTextureMetrics(const TextureMetricsParams& params);

}  // namespace tdvo
