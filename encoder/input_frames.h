// The encoder's input frames and how geometry and textures are tied by frame number.
//
// Every coded frame has a frame number, the input's: stream frame k is frame number
// FirstFrame + k. That number names the geometry file (InputMeshPattern filled with it) and,
// with a Dataset, the dataset frame whose camera images are its texture (dataset frame number
// n = frames.first + index, docs/dataset.md); without InputMeshPattern the dataset's meshes
// are the geometry, also by frame number. The sequence header records FirstFrame
// (sh_first_frame), so the decoder names its output with the same numbers.
#pragma once

#include <string>

#include "common/media/dataset.h"
#include "encoder/encoder_params.h"

namespace tdvo {

// The geometry file of frame number `frame`: InputMeshPattern's, else the dataset's meshes.
// Throws Error when the frame is not in the dataset (naming its dataset.json).
std::string inputMeshPath(const EncoderParams& params, const Dataset* dataset, int frame);

// The frames to code, FrameCount of them from FirstFrame; when FrameCount is 0, every
// consecutive frame from FirstFrame on until the first missing geometry file (or, with a
// dataset, its last frame). `found` (when given) receives a line saying how many were found
// and why the count stopped. Throws Error when there is no frame at all.
int resolveFrameCount(const EncoderParams& params, const Dataset* dataset,
                      std::string* found = nullptr);

// With a dataset: checks that every coded frame number FirstFrame .. FirstFrame + count - 1 is a
// frame of the dataset (geometry and texture of each frame tied by its number); an Error names
// the geometry file and the dataset otherwise.
void checkTextureFrames(const EncoderParams& params, const Dataset& dataset, int count);

}  // namespace tdvo
