// The synthetic capture rig: renders a mesh sequence with a stable procedural surface texture
// into N calibrated cameras and writes a dataset (common/media/dataset.h) with exact ground truth:
// per-camera image sequences, masks (the rasteriser's coverage of the ground-truth mesh),
// calibration, background images and the meshes themselves.
#pragma once

#include <string>
#include <vector>

#include "common/core/config.h"
#include "common/media/dataset.h"
#include "common/views/camera.h"

namespace tdvo {

enum class RigLayout { ring, dome };

struct SynthParams {
  std::string output;            // dataset folder to write
  bool overwrite = false;        // replace a non-empty output folder's contents
  std::string inputMeshPattern;  // OBJ sequence; empty: the built-in deforming blob
  int firstFrame = 0;            // number of the first input mesh
  int frameCount = 10;           // frames to render
  int blobSubdivisions = 4;      // built-in blob: icosphere level (2562 vertices at 4)
  int cameras = 8;
  RigLayout layout = RigLayout::ring;
  int width = 320, height = 240;
  double fieldOfView = 45;   // horizontal, degrees (used when focalLength is 0)
  double focalLength = 0;    // pixels; 0: from fieldOfView
  double elevation = 15;     // ring: camera height angle above the object's centre, degrees
  double distance = 0;       // camera distance to the centre; 0: fit the object in view
  std::string up = "0,1,0";  // the world's up direction
  std::string backgroundColour = "48,52,60";
  std::string backgroundImage;  // PNG, scaled to each camera's size; replaces the colour
  double noiseSigma = 0;        // camera noise, grey levels (approximately Gaussian)
  int seed = 1;                 // noise seed
};

// Registers the rig's keys (sections Output, Content, Rig, Appearance) in an option table.
void addSynthOptions(OptionTable& table, SynthParams& params);

// The rig's cameras around a bounding sphere (centre, radius) of the content.
std::vector<Camera> makeRigCameras(const SynthParams& params, const Vec3d& centre, double radius);

// Renders and writes the dataset to params.output (all files staged and renamed together at the
// end, so a failed run leaves nothing under the final names). Same inputs give byte-identical
// files. Progress goes to stderr when it is a terminal. Returns the dataset written.
Dataset writeSyntheticDataset(const SynthParams& params);

}  // namespace tdvo
