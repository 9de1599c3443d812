#include "common/core/mesh_attributes.h"

#include <cmath>
#include <cstdint>
#include <map>
#include <utility>

namespace tdvo {

namespace {

constexpr uint32_t kNone = UINT32_MAX;

bool perVertex(const std::vector<Triangle>& indices, size_t values, const Mesh& mesh) {
  return values == mesh.positions.size() && indices == mesh.triangles;
}

}  // namespace

std::vector<Vec2f> uvsFrom(const MeshAttributes& a, UvOrigin origin) {
  std::vector<Vec2f> uvs = a.uvs;
  if (a.uvOrigin != origin)
    for (Vec2f& uv : uvs)
      uv[1] = 1.0f - uv[1];
  return uvs;
}

void setUvOrigin(MeshAttributes& a, UvOrigin origin) {
  if (a.uvOrigin != origin) a.uvs = uvsFrom(a, origin);
  a.uvOrigin = origin;
}

bool attributesPerVertex(const Mesh& mesh) {
  const MeshAttributes& a = mesh.attributes;
  return (!a.hasUvs() || perVertex(a.uvTriangles, a.uvs.size(), mesh)) &&
         (!a.hasNormals() || perVertex(a.normalTriangles, a.normals.size(), mesh));
}

Mesh splitAttributeSeams(const Mesh& mesh, size_t* copies) {
  if (copies) *copies = 0;
  if (mesh.attributes.empty() || attributesPerVertex(mesh)) return mesh;
  const MeshAttributes& in = mesh.attributes;
  const bool uvs = in.hasUvs(), normals = in.hasNormals();
  Mesh out;
  out.positions = mesh.positions;
  out.triangles = mesh.triangles;
  const size_t n = mesh.positions.size();
  // The (texture coordinate, normal) indices of each output vertex; kNone: not yet taken.
  std::vector<std::pair<uint32_t, uint32_t>> key(n, {kNone, kNone});
  std::map<std::pair<uint32_t, std::pair<uint32_t, uint32_t>>, uint32_t> split;
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const uint32_t v = mesh.triangles[t][c];
      const std::pair<uint32_t, uint32_t> k{uvs ? in.uvTriangles[t][c] : 0,
                                            normals ? in.normalTriangles[t][c] : 0};
      if (key[v].first == kNone) key[v] = k;
      if (key[v] == k) continue;
      auto [it, added] = split.insert({{v, k}, static_cast<uint32_t>(out.positions.size())});
      if (added) {
        out.positions.push_back(mesh.positions[v]);
        key.push_back(k);
      }
      out.triangles[t][c] = it->second;
    }
  if (copies) *copies = out.positions.size() - n;
  const bool uvsPerVertex = uvs && perVertex(in.uvTriangles, in.uvs.size(), mesh);
  const bool normalsPerVertex = normals && perVertex(in.normalTriangles, in.normals.size(), mesh);
  for (size_t v = 0; v < out.positions.size(); ++v) {
    const bool used = key[v].first != kNone;
    if (uvs)
      out.attributes.uvs.push_back(used           ? in.uvs[key[v].first]
                                   : uvsPerVertex ? in.uvs[v]
                                                  : Vec2f{0, 0});
    if (normals)
      out.attributes.normals.push_back(used               ? in.normals[key[v].second]
                                       : normalsPerVertex ? in.normals[v]
                                                          : Vec3f{0, 0, 0});
  }
  if (uvs) out.attributes.uvTriangles = out.triangles;
  if (normals) out.attributes.normalTriangles = out.triangles;
  out.attributes.uvOrigin = in.uvOrigin;
  return out;
}

std::vector<Vec3f> computeVertexNormals(const std::vector<Vec3i>& positions,
                                        const std::vector<Triangle>& triangles) {
  // A cross product is below 2^41 per component (coordinates below 2^20), a vertex is in fewer
  // than 2^25 triangles: the sums fit in 128 bits.
  std::vector<std::array<__int128, 3>> sum(positions.size(), {0, 0, 0});
  for (const Triangle& t : triangles) {
    const Vec3i &a = positions[t[0]], &b = positions[t[1]], &c = positions[t[2]];
    const int64_t u[3] = {int64_t{b[0]} - a[0], int64_t{b[1]} - a[1], int64_t{b[2]} - a[2]};
    const int64_t w[3] = {int64_t{c[0]} - a[0], int64_t{c[1]} - a[1], int64_t{c[2]} - a[2]};
    const int64_t cross[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                              u[0] * w[1] - u[1] * w[0]};
    for (uint32_t v : t)
      for (int k = 0; k < 3; ++k)
        sum[v][k] += cross[k];
  }
  std::vector<Vec3f> normals(positions.size(), Vec3f{0, 0, 0});
  for (size_t v = 0; v < sum.size(); ++v) {
    const double x = double(sum[v][0]), y = double(sum[v][1]), z = double(sum[v][2]);
    const double length = std::sqrt(x * x + y * y + z * z);
    if (length > 0) normals[v] = {float(x / length), float(y / length), float(z / length)};
  }
  return normals;
}

}  // namespace tdvo
