// Google Benchmark micro-benchmarks of the denoiser's two stages and its set-up, on a noisy icosphere
// built in code (so they run anywhere) with 20 * 4^level faces.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>

#include "scanmesh/add_noise.h"
#include "scanmesh/denoise.h"
#include "scanmesh/normal_filtering.h"
#include "scanmesh/parallel.h"
#include "scanmesh/vertex_update.h"

using namespace scanmesh;

namespace {

Mesh noisy_sphere(int levels) {
  Mesh m;
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  for (const auto& p : {Vec3(-1, t, 0), Vec3(1, t, 0), Vec3(-1, -t, 0), Vec3(1, -t, 0), Vec3(0, -1, t), Vec3(0, 1, t),
                        Vec3(0, -1, -t), Vec3(0, 1, -t), Vec3(t, 0, -1), Vec3(t, 0, 1), Vec3(-t, 0, -1), Vec3(-t, 0, 1)})
    m.positions.push_back(p.normalized());
  m.faces = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
             {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto [it, inserted] = mid.try_emplace(std::minmax(a, b), static_cast<int>(m.positions.size()));
      if (inserted) m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
      return it->second;
    };
    std::vector<Face> faces;
    for (const Face& f : m.faces) {
      const int a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      faces.insert(faces.end(), {{f[0], a, c}, {f[1], b, a}, {f[2], c, b}, {a, b, c}});
    }
    m.faces = std::move(faces);
  }
  add_noise(m, NoiseOptions{});
  return m;
}

struct Fixture {
  Mesh mesh;
  Topology topology;
  FaceGeometry geometry;
  Adjacency neighbourhoods;
  double c_a = 0.0;
  explicit Fixture(int levels) : mesh(noisy_sphere(levels)), topology(build_topology(mesh)) {
    compute_face_geometry(mesh.positions, mesh.faces, geometry);
    c_a = mean_centroid_distance(mesh, topology, geometry);
    neighbourhoods = face_neighbourhoods(topology, geometry, 2.0 * c_a, NeighbourhoodKind::ball);
  }
};

const Fixture& fixture(int levels) {
  static std::map<int, Fixture> cache;
  auto it = cache.find(levels);
  if (it == cache.end()) it = cache.emplace(levels, Fixture(levels)).first;
  return it->second;
}

void BM_FilterFaceNormals(benchmark::State& state) {
  set_thread_count(static_cast<int>(state.range(1)));
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  std::vector<Vec3> filtered;
  for (auto _ : state) {
    filter_face_normals(f.geometry, f.neighbourhoods, f.c_a, 0.55, RobustEstimator::tukey, filtered);
    benchmark::DoNotOptimize(filtered.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(f.mesh.num_faces()));
}

void BM_UpdateVertices(benchmark::State& state) {
  set_thread_count(static_cast<int>(state.range(1)));
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  std::vector<Vec3> updated;
  for (auto _ : state) {
    update_vertices(f.mesh.positions, f.topology, f.geometry, f.geometry.normals, 0.2, nullptr, false, updated);
    benchmark::DoNotOptimize(updated.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(f.mesh.num_vertices()));
}

void BM_Neighbourhoods(benchmark::State& state) {
  set_thread_count(static_cast<int>(state.range(1)));
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(face_neighbourhoods(f.topology, f.geometry, 2.0 * f.c_a, NeighbourhoodKind::ball));
  state.SetItemsProcessed(state.iterations() * static_cast<long>(f.mesh.num_faces()));
}

void BM_Topology(benchmark::State& state) {
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(build_topology(f.mesh));
  state.SetItemsProcessed(state.iterations() * static_cast<long>(f.mesh.num_faces()));
}

void BM_Denoise20(benchmark::State& state) {
  set_thread_count(static_cast<int>(state.range(1)));
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  DenoiseOptions o;
  o.iterations = 20;
  for (auto _ : state) {
    Mesh m = f.mesh;
    denoise(m, o);
    benchmark::DoNotOptimize(m.positions.data());
  }
}

// Level 5 = 20k faces, level 6 = 82k faces; 1 and 2 threads.
BENCHMARK(BM_FilterFaceNormals)->ArgsProduct({{5, 6}, {1, 2}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UpdateVertices)->ArgsProduct({{5, 6}, {1, 2}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Neighbourhoods)->ArgsProduct({{5, 6}, {1, 2}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Topology)->Args({6})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Denoise20)->ArgsProduct({{6}, {1, 2}})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
