#include "common/core/md5.h"

#include <md5.h>

#include <cstring>

namespace tdvo {

Md5::Md5() : context_(new MD5_CTX) {
  MD5Init(static_cast<MD5_CTX*>(context_));
}

Md5::~Md5() {
  delete static_cast<MD5_CTX*>(context_);
}

void Md5::update(const void* data, size_t size) {
  MD5Update(static_cast<MD5_CTX*>(context_), static_cast<const uint8_t*>(data), size);
}

void Md5::updateU32(uint32_t value) {
  const uint8_t bytes[4] = {static_cast<uint8_t>(value), static_cast<uint8_t>(value >> 8),
                            static_cast<uint8_t>(value >> 16), static_cast<uint8_t>(value >> 24)};
  update(bytes, 4);
}

Md5Digest Md5::finish() {
  Md5Digest digest{};
  MD5Final(digest.data(), static_cast<MD5_CTX*>(context_));
  return digest;
}

std::string toHex(const Md5Digest& digest) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  for (uint8_t b : digest) {
    out += kHex[b >> 4];
    out += kHex[b & 15];
  }
  return out;
}

Md5Digest geometryDigest(const IntMesh& mesh) {
  // Serialised through a fixed buffer hashed whenever it fills: one MD5Update call per value would
  // dominate decoding time, and a buffer of the whole frame would be an allocation per frame.
  uint8_t buffer[1 << 14];
  size_t used = 0;
  Md5 md5;
  auto put = [&](uint32_t v) {
    if (used + 4 > sizeof buffer) {
      md5.update(buffer, used);
      used = 0;
    }
    for (int shift = 0; shift < 32; shift += 8)
      buffer[used++] = static_cast<uint8_t>(v >> shift);
  };
  put(static_cast<uint32_t>(mesh.positions.size()));
  put(static_cast<uint32_t>(mesh.triangles.size()));
  for (const Vec3i& p : mesh.positions)
    for (int32_t c : p)
      put(static_cast<uint32_t>(c));
  for (const Triangle& t : mesh.triangles)
    for (uint32_t v : t)
      put(v);
  // Texture coordinates and normals, when the frame has any (docs/bitstream.md section 8):
  // each as its value count, the values' float32 bit patterns, and (when there are values)
  // the index triangles. A frame without them hashes as before.
  const MeshAttributes& a = mesh.attributes;
  auto putAttribute = [&](const auto& values, const std::vector<Triangle>& indices) {
    put(static_cast<uint32_t>(values.size()));
    for (const auto& value : values)
      for (float f : value) {
        uint32_t bits;
        std::memcpy(&bits, &f, 4);
        put(bits);
      }
    if (values.empty()) return;
    for (const Triangle& t : indices)
      for (uint32_t v : t)
        put(v);
  };
  if (!a.empty()) {
    putAttribute(a.uvs, a.uvTriangles);
    putAttribute(a.normals, a.normalTriangles);
    // Texture coordinates whose v = 0 is the image's top row (at_uv_origin 1) add a 1; those of
    // the bottom row (0, every stream before syntax version 6) hash as before.
    if (a.hasUvs() && a.uvOrigin == UvOrigin::kTop) put(1);
  }
  md5.update(buffer, used);
  return md5.finish();
}

std::string geometryHashLine(int frame, const IntMesh& mesh) {
  return "MD5 frame=" + std::to_string(frame) + " geometry=" + toHex(geometryDigest(mesh));
}

}  // namespace tdvo
