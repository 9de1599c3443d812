// Speed of the geometry metrics (tools/eval/metrics.h) on meshes of the size 3DVO works with.
//
//   build/bin/metrics_bench --benchmark_filter=Hausdorff
//
// Target (issue 4): the symmetric Hausdorff distance between two ~20k-vertex meshes, spatial
// indices included, in well under a second.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

#include "common/core/obj_io.h"
#include "tools/eval/metrics.h"

using namespace tdvo;

namespace {

// A latitude/longitude sphere of radius ~1 with `rings` x `segments` vertices, its radius
// modulated by `bumps` so that two such meshes are different surfaces. The rings start half a
// step away from the poles (no coincident vertices); the two polar caps are left open.
Mesh bumpySphere(int rings, int segments, double bumps) {
  const double pi = std::acos(-1.0);
  Mesh m;
  for (int i = 0; i < rings; ++i) {
    const double theta = pi * (i + 0.5) / rings;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2 * pi * j / segments;
      const double r = 1.0 + bumps * std::sin(5 * theta) * std::cos(3 * phi);
      m.positions.push_back({r * std::sin(theta) * std::cos(phi),
                             r * std::sin(theta) * std::sin(phi), r * std::cos(theta)});
    }
  }
  for (int i = 0; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const uint32_t a = static_cast<uint32_t>(i * segments + j);
      const uint32_t b = static_cast<uint32_t>(i * segments + (j + 1) % segments);
      const uint32_t c = a + static_cast<uint32_t>(segments),
                     d = b + static_cast<uint32_t>(segments);
      m.triangles.push_back({a, c, d});
      m.triangles.push_back({a, d, b});
    }
  return m;
}

// Two different ~20k-vertex surfaces: 140 x 143 = 20,020 and 143 x 140 vertices.
// items_per_second: sample vertices (both directions) per second, spatial indices included.
void BM_Hausdorff20k(benchmark::State& state) {
  const Mesh reference = bumpySphere(140, 143, 0.02);
  const Mesh test = bumpySphere(143, 140, 0.025);
  for (auto _ : state) {
    const SurfaceDistance d = surfaceDistance(reference, test);
    benchmark::DoNotOptimize(d.hausdorff());
  }
  state.counters["vertices"] = static_cast<double>(reference.positions.size());
  state.counters["triangles"] = static_cast<double>(reference.triangles.size());
  state.SetItemsProcessed(int64_t(state.iterations()) *
                          int64_t(reference.positions.size() + test.positions.size()));
}
BENCHMARK(BM_Hausdorff20k)->Unit(benchmark::kMillisecond);

// The index alone (construction happens twice per Hausdorff call).
void BM_SurfaceIndexBuild20k(benchmark::State& state) {
  const Mesh mesh = bumpySphere(140, 143, 0.02);
  for (auto _ : state) {
    SurfaceIndex index(mesh);
    benchmark::DoNotOptimize(index.triangleCount());
  }
}
BENCHMARK(BM_SurfaceIndexBuild20k)->Unit(benchmark::kMillisecond);

// The nearest-vertex correspondence used for decoded frames (20k vertices, shuffled order).
void BM_NearestCorrespondence20k(benchmark::State& state) {
  const Mesh reference = bumpySphere(140, 143, 0.02);
  std::vector<Vec3d> test = reference.positions;
  // A fixed shuffle with a small offset: every vertex still nearest to its original.
  uint64_t seed = 12345;
  for (size_t i = test.size() - 1; i > 0; --i) {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    std::swap(test[i], test[(seed >> 33) % (i + 1)]);
  }
  for (Vec3d& p : test)
    p[0] += 1e-4;
  for (auto _ : state)
    benchmark::DoNotOptimize(nearestVertexCorrespondence(reference.positions, test).data());
}
BENCHMARK(BM_NearestCorrespondence20k)->Unit(benchmark::kMillisecond);

// Real data when present: samba frames 0 and 1 (9,971 vertices each).
void BM_HausdorffSamba(benchmark::State& state) {
  const std::string folder = std::string(TDVO_SHARED_DATA_DIR) + "/meshseq/samba/";
  if (!std::filesystem::exists(folder + "mesh_0000.obj.gz")) {
    state.SkipWithError(("shared data not found at " + folder).c_str());
    return;
  }
  const Mesh reference = readObj(folder + "mesh_0000.obj.gz");
  const Mesh test = readObj(folder + "mesh_0001.obj.gz");
  for (auto _ : state) {
    const SurfaceDistance d = surfaceDistance(reference, test);
    benchmark::DoNotOptimize(d.hausdorff());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) *
                          int64_t(reference.positions.size() + test.positions.size()));
}
BENCHMARK(BM_HausdorffSamba)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
