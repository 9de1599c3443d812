// Export of a dataset-layout folder (a dataset, or a decoded 3DVO) into what the web player in
// tools/player/ loads (docs/rendering.md, "Player data"):
//
//   scene.json            cameras, frame count and rate, GOM starts, atlas layout, the bounding
//                         sphere and up direction, the renderer's default weighting options
//   meshes/NNNN.bin       per frame: uint32 vertex count V, uint32 triangle count T (little
//                         endian), V × 3 float32 positions, T × 3 uint32 vertex indices
//   textures/NNNN.png     per frame: RGBA atlas of every camera's image, camera k in cell
//                         (k mod columns, k div columns) of cellWidth × cellHeight pixels, top-left
//                         aligned; alpha is the camera's mask (255 where it has none)
//
// NNNN counts the exported frames from 0.
#pragma once

#include <string>
#include <vector>

#include "common/media/dataset.h"
#include "tools/render/view_renderer.h"

namespace tdvo {

struct PlayerExportParams {
  std::string output;               // folder to write
  bool overwrite = false;           // replace a non-empty output folder's contents
  std::vector<std::string> inputs;  // files the output folder must not hold when replaced
  std::vector<int> frames;          // dataset frame indices to export, in order
  std::vector<int> gomStarts;       // positions in `frames` where a GOM starts (empty: every frame)
  RenderOptions options;            // written as the player's default weighting
};

// Writes the player data (all files staged and renamed together at the end).
void exportPlayerData(const Dataset& dataset, const PlayerExportParams& params);

// The largest atlas side the export writes (WebGL 2 guarantees far less; SwiftShader and common
// GPUs give 8192).
constexpr int kMaxAtlasSide = 8192;

}  // namespace tdvo
