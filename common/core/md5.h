// MD5 digests of decoded data, printed like HM's picture hash so that conformance is a text
// comparison. The digest itself comes from libmd (Debian's libmd-dev), a small library with no
// other dependency.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "common/core/mesh.h"

namespace tdvo {

using Md5Digest = std::array<uint8_t, 16>;

class Md5 {
 public:
  Md5();
  ~Md5();
  Md5(const Md5&) = delete;
  Md5& operator=(const Md5&) = delete;
  void update(const void* data, size_t size);
  void updateU32(uint32_t value);  // 4 bytes, little-endian
  Md5Digest finish();

 private:
  void* context_;
};

std::string toHex(const Md5Digest& digest);

// The geometry digest of one decoded frame. Byte layout (docs/bitstream.md, "Frame hashes"):
// vertex count (u32 LE), triangle count (u32 LE), then per vertex x y z as int32 LE, then per
// triangle its three vertex indices as u32 LE; then, only when the frame has texture
// coordinates or normals, for each of the two: its value count (u32 LE), every value's float32
// bit pattern (u32 LE), and when the count is not 0 its index triangles (u32 LE).
Md5Digest geometryDigest(const IntMesh& mesh);

// "MD5 frame=<n> geometry=<32 hex digits>", the line encoder and decoder print per frame.
std::string geometryHashLine(int frame, const IntMesh& mesh);

}  // namespace tdvo
