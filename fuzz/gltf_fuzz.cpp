// Fuzz target: the glTF reader (GltfFile from memory, through tinygltf), its first frames, plus a
// property check: a frame it accepts, written with formatGltf (.glb) and read again, has the
// same triangles and its positions as float.
//
// The input is a .gltf or .glb file (external buffers are refused from memory). Seeds: frame 0
// of each conformance input as .gltf and .glb, and an animated .glb of its first frames
// (fuzz_make_corpus).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/core/gltf_io.h"
#include "common/core/warnings.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // What the reader leaves out it says (warnings.h): not on stderr at every input here.
  static const bool quiet = (tdvo::setWarningHandler([](const std::string&) {}), true);
  (void)quiet;
  const std::vector<uint8_t> bytes(data, data + size);
  try {
    const tdvo::GltfFile file(bytes, "fuzz.glb");
    // A few frames: each is made on demand, and an animation may have many keyframes.
    for (size_t k = 0; k < file.frameCount() && k < 4; ++k) {
      tdvo::Mesh mesh;
      try {
        mesh = file.frame(k);
      } catch (const tdvo::Error&) {
        continue;
      }
      const std::string glb = tdvo::formatGltf(mesh, tdvo::GltfContainer::kGlb);
      const tdvo::Mesh again =
          tdvo::GltfFile(std::vector<uint8_t>(glb.begin(), glb.end()), "formatted.glb").frame(0);
      bool same =
          again.triangles == mesh.triangles && again.positions.size() == mesh.positions.size();
      for (size_t i = 0; same && i < mesh.positions.size(); ++i)
        for (int c = 0; c < 3; ++c)
          same &= again.positions[i][c] ==
                  static_cast<double>(static_cast<float>(mesh.positions[i][c]));
      if (!same) {
        std::fprintf(stderr, "gltf fuzz target: formatGltf output does not read back\n");
        std::abort();
      }
    }
  } catch (const tdvo::Error&) {
    return 0;
  }
  return 0;
}
