// The mesh sequences the benchmarks run on, so that every figure names its input:
//   horse-gallop  ../shared/data/meshseq/horse-gallop, 48 frames, 8,431 vertices
//   samba         ../shared/data/meshseq/samba, 175 frames, 9,971 vertices
// and, when neither is present, "blob": the generated deforming icosphere of
// tools/eval/sample_mesh.h (5 subdivisions: 10,242 vertices, 48 frames). Each benchmark program
// adds a context line per sequence ("sequence.<name>: <source>") to its output header.
#pragma once

#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <vector>

#include "common/core/mesh.h"
#include "common/core/obj_io.h"
#include "common/core/sequence.h"
#include "tools/eval/sample_mesh.h"

namespace tdvo {
namespace bench {

struct BenchSequence {
  std::string name;
  std::string source;   // where the frames came from
  std::string pattern;  // printf pattern of the files ("" for the generated blob)
  int firstFrame = 0;
  int frameCount = 0;
  int gomSize = 16;  // the GOM size of cfg/per-sequence/<name>.cfg
};

// The sequences available here (shared data when present, else the blob); frames not loaded.
inline std::vector<BenchSequence> benchSequences() {
  const std::string data = std::string(TDVO_SHARED_DATA_DIR) + "/meshseq/";
  std::vector<BenchSequence> all = {
      {"horse-gallop", data + "horse-gallop/%04d.obj.gz", data + "horse-gallop/%04d.obj.gz", 1, 48,
       48},
      {"samba", data + "samba/mesh_%04d.obj.gz", data + "samba/mesh_%04d.obj.gz", 0, 175, 25},
  };
  std::vector<BenchSequence> present;
  for (const BenchSequence& s : all)
    if (std::filesystem::exists(framePath(s.pattern, s.firstFrame + s.frameCount - 1)))
      present.push_back(s);
  if (present.empty())
    present.push_back(
        {"blob", "generated: deformingBlob(5 subdivisions, 48 frames)", "", 0, 48, 16});
  for (const BenchSequence& s : present)
    benchmark::AddCustomContext("sequence." + s.name, s.source);
  return present;
}

inline std::vector<Mesh> loadFrames(const BenchSequence& s) {
  if (s.pattern.empty()) return deformingBlob(5, s.frameCount);
  std::vector<Mesh> frames;
  for (int k = 0; k < s.frameCount; ++k)
    frames.push_back(readObj(framePath(s.pattern, s.firstFrame + k)));
  return frames;
}

}  // namespace bench
}  // namespace tdvo
