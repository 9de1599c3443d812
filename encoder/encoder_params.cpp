#include "encoder/encoder_params.h"

#include "common/error.h"
#include "common/sequence.h"

namespace tdvo {

void EncoderParams::registerOptions(OptionTable& t) {
  t.section("Input");
  t.add("InputMeshPattern", inputMeshPattern,
        "input OBJ frames as a printf pattern, e.g. seq/%04d.obj (.obj.gz read through zlib)");
  t.add("FirstFrame", firstFrame, 0, 1000000000, "number of the first input frame");
  t.add("FrameCount", frameCount, 1, static_cast<int>(kMaxFrames), "number of frames to code");
  t.add("FrameRate", frameRate, 0.001, 1000, "frames per second (rate figures, stream header)");
  t.section("Geometry");
  t.add("GridBits", gridBits, 8, 20,
        "bits per coordinate of the integer grid spanning the sequence's bounding box");
  t.add("GOMSize", gomSize, 1, static_cast<int>(kMaxGomFrames),
        "frames per group of meshes (GOM); each GOM starts with an I mesh");
  t.addEnum("PMeshMode", pmeshMode, {{"intra", PMeshMode::kIntra}},
            "coding of the frames after a GOM's first: intra = every frame an I mesh");
  t.add("DracoSpeed", dracoSpeed, 0, 10, "Draco speed for I meshes: 0 = smallest, 10 = fastest");
  t.section("Output");
  t.add("BitstreamFile", bitstreamFile, "the .3dvo stream to write", "-o");
  t.add("ReconMeshPattern", reconMeshPattern,
        "optional: write the encoder's reconstruction as OBJ frames (printf pattern, frame "
        "numbers from 0)");
}

void EncoderParams::validate() const {
  check(!inputMeshPattern.empty(), "InputMeshPattern is not set (see --help)");
  check(!bitstreamFile.empty(), "BitstreamFile is not set (see --help)");
  checkFramePattern(inputMeshPattern, "InputMeshPattern");
  if (!reconMeshPattern.empty()) checkFramePattern(reconMeshPattern, "ReconMeshPattern");
}

}  // namespace tdvo
