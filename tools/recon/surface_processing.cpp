#include "tools/recon/surface_processing.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalDeviationT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <OpenMesh/Tools/Smoother/JacobiLaplaceSmootherT.hh>
#include <algorithm>
#include <numeric>

namespace tdvo {

namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
};
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

thread_local size_t droppedTriangles = 0;

OmMesh toOpenMesh(const Mesh& mesh) {
  // OpenMesh reports refused faces on its error stream; they are counted here instead.
  omerr().disable();
  OmMesh om;
  std::vector<OmMesh::VertexHandle> handles;
  handles.reserve(mesh.positions.size());
  for (const Vec3d& p : mesh.positions)
    handles.push_back(om.add_vertex(OmMesh::Point(p[0], p[1], p[2])));
  droppedTriangles = 0;
  for (const Triangle& t : mesh.triangles) {
    const OmMesh::FaceHandle f = om.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
    if (!f.is_valid()) ++droppedTriangles;
  }
  return om;
}

// Back to a Mesh: deleted elements are skipped and isolated vertices dropped.
Mesh fromOpenMesh(OmMesh& om) {
  if (om.has_vertex_status() && om.has_face_status()) om.garbage_collection();
  Mesh mesh;
  std::vector<int64_t> index(om.n_vertices(), -1);
  for (const auto& f : om.faces()) {
    Triangle t;
    int k = 0;
    for (const auto& v : f.vertices()) {
      int64_t& i = index[static_cast<size_t>(v.idx())];
      if (i < 0) {
        i = static_cast<int64_t>(mesh.positions.size());
        const OmMesh::Point& p = om.point(v);
        mesh.positions.push_back({p[0], p[1], p[2]});
      }
      t[static_cast<size_t>(k++)] = static_cast<uint32_t>(i);
    }
    mesh.triangles.push_back(t);
  }
  return mesh;
}

}  // namespace

size_t lastDroppedTriangles() {
  return droppedTriangles;
}

size_t weldVertices(Mesh& mesh) {
  std::vector<uint32_t> order(mesh.positions.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return mesh.positions[a] < mesh.positions[b] ||
           (mesh.positions[a] == mesh.positions[b] && a < b);
  });
  std::vector<uint32_t> representative(mesh.positions.size());
  for (size_t i = 0; i < order.size(); ++i)
    representative[order[i]] = i > 0 && mesh.positions[order[i]] == mesh.positions[order[i - 1]]
                                   ? representative[order[i - 1]]
                                   : order[i];
  Mesh welded;
  std::vector<int64_t> index(mesh.positions.size(), -1);
  for (uint32_t v = 0; v < mesh.positions.size(); ++v)
    if (representative[v] == v) {
      index[v] = static_cast<int64_t>(welded.positions.size());
      welded.positions.push_back(mesh.positions[v]);
    }
  for (const Triangle& t : mesh.triangles) {
    Triangle out;
    for (size_t k = 0; k < 3; ++k)
      out[k] = static_cast<uint32_t>(index[representative[t[k]]]);
    if (out[0] != out[1] && out[1] != out[2] && out[0] != out[2]) welded.triangles.push_back(out);
  }
  const size_t removed = mesh.positions.size() - welded.positions.size();
  mesh = std::move(welded);
  return removed;
}

size_t keepLargestComponent(Mesh& mesh) {
  // Union-find over the vertices joined by triangle edges.
  std::vector<uint32_t> parent(mesh.positions.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&parent](uint32_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  for (const Triangle& t : mesh.triangles)
    for (int k = 1; k < 3; ++k) {
      const uint32_t a = find(t[0]), b = find(t[static_cast<size_t>(k)]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  std::vector<size_t> faces(mesh.positions.size(), 0);
  for (const Triangle& t : mesh.triangles)
    ++faces[find(t[0])];
  size_t components = 0;
  uint32_t best = 0;
  for (uint32_t v = 0; v < faces.size(); ++v) {
    if (faces[v] == 0) continue;
    ++components;
    if (faces[v] > faces[best] || faces[best] == 0) best = v;
  }
  if (components == 0) return 0;
  Mesh kept;
  std::vector<int64_t> index(mesh.positions.size(), -1);
  for (const Triangle& t : mesh.triangles) {
    if (find(t[0]) != best) continue;
    Triangle out;
    for (int k = 0; k < 3; ++k) {
      int64_t& i = index[t[static_cast<size_t>(k)]];
      if (i < 0) {
        i = static_cast<int64_t>(kept.positions.size());
        kept.positions.push_back(mesh.positions[t[static_cast<size_t>(k)]]);
      }
      out[static_cast<size_t>(k)] = static_cast<uint32_t>(i);
    }
    kept.triangles.push_back(out);
  }
  mesh = std::move(kept);
  return components;
}

void smoothMesh(Mesh& mesh, const SmoothingOptions& options) {
  if (options.iterations <= 0 || mesh.triangles.empty()) return;
  OmMesh om = toOpenMesh(mesh);
  om.request_vertex_normals();
  om.update_normals();
  OpenMesh::Smoother::JacobiLaplaceSmootherT<OmMesh> smoother(om);
  smoother.initialize(OpenMesh::Smoother::SmootherT<OmMesh>::Tangential_and_Normal,
                      OpenMesh::Smoother::SmootherT<OmMesh>::C0);
  if (options.maxDisplacement > 0) smoother.set_absolute_local_error(options.maxDisplacement);
  smoother.smooth(static_cast<unsigned>(options.iterations));
  mesh = fromOpenMesh(om);
}

size_t decimateMesh(Mesh& mesh, const DecimationOptions& options) {
  if (mesh.triangles.empty()) return 0;
  if (options.targetFaces > 0 && mesh.triangles.size() <= options.targetFaces) return 0;
  OmMesh om = toOpenMesh(mesh);
  om.update_face_normals();
  using Decimater = OpenMesh::Decimater::DecimaterT<OmMesh>;
  Decimater decimater(om);
  OpenMesh::Decimater::ModNormalDeviationT<OmMesh>::Handle normalDeviation;
  decimater.add(normalDeviation);
  decimater.module(normalDeviation).set_normal_deviation(options.maxNormalDeviation);
  decimater.module(normalDeviation).set_binary(false);
  OpenMesh::Decimater::ModQuadricT<OmMesh>::Handle quadric;
  if (options.maxError > 0) {
    decimater.add(quadric);
    decimater.module(quadric).set_max_err(options.maxError, false);
    decimater.module(quadric).set_binary(true);
  }
  decimater.initialize();
  const size_t collapses = options.targetFaces > 0
                               ? decimater.decimate_to_faces(0, options.targetFaces)
                               : decimater.decimate(0);
  mesh = fromOpenMesh(om);
  return collapses;
}

}  // namespace tdvo
