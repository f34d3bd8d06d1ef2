// Google Benchmark micro-benchmarks of the denoiser's two stages and its set-up, on a noisy icosphere
// built in code (so they run anywhere) with 20 * 4^level faces.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>

#include "helpers.h"
#include "scanmesh/add_noise.h"
#include "scanmesh/denoise.h"
#include "scanmesh/normal_filtering.h"
#include "scanmesh/parallel.h"
#include "scanmesh/vertex_update.h"

using namespace scanmesh;

namespace {

Mesh noisy_sphere(int levels) {
  Mesh m = test::make_sphere(levels);
  add_noise(m, NoiseOptions{});
  return m;
}

struct Fixture {
  Mesh mesh;
  Topology topology;
  FaceGeometry geometry;
  PackedRows neighbourhoods;  // as the denoiser holds them
  PackedRows fidelity;
  double c_a = 0.0;
  explicit Fixture(int levels) : mesh(noisy_sphere(levels)), topology(build_topology(mesh)) {
    compute_face_geometry(mesh.positions, mesh.faces, geometry);
    c_a = mean_centroid_distance(mesh, topology, geometry);
    neighbourhoods = packed_face_neighbourhoods(topology, geometry, 2.0 * c_a, NeighbourhoodKind::ball, max_neighbourhood_size(2.0));
    fidelity = PackedRows::from(topology.vertex_vertices);
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
  set_filter_isa(state.range(2) != 0 ? FilterIsa::sse2 : FilterIsa::best);
  std::vector<Vec3> filtered;
  for (auto _ : state) {
    filter_face_normals(f.geometry, f.neighbourhoods, f.c_a, 0.55, RobustEstimator::tukey, filtered);
    benchmark::DoNotOptimize(filtered.data());
  }
  set_filter_isa(FilterIsa::best);
  state.SetItemsProcessed(state.iterations() * static_cast<long>(f.mesh.num_faces()));
}

void BM_UpdateVertices(benchmark::State& state) {
  set_thread_count(static_cast<int>(state.range(1)));
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  std::vector<Vec3> updated;
  for (auto _ : state) {
    VertexUpdateTerms terms;
    terms.lambda = 0.2;
    update_vertices(f.mesh.positions, f.topology, f.fidelity, f.geometry, f.geometry.normals, terms, updated);
    benchmark::DoNotOptimize(updated.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(f.mesh.num_vertices()));
}

void BM_Neighbourhoods(benchmark::State& state) {
  set_thread_count(static_cast<int>(state.range(1)));
  const Fixture& f = fixture(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(packed_face_neighbourhoods(f.topology, f.geometry, 2.0 * f.c_a, NeighbourhoodKind::ball, max_neighbourhood_size(2.0)));
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

// Level 5 = 20k faces, level 6 = 82k faces, level 8 = 1.3M faces; 1 and 2 threads; the filter also with
// its SSE2 path forced (third argument 1).
BENCHMARK(BM_FilterFaceNormals)->ArgsProduct({{5, 6, 8}, {1, 2}, {0, 1}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UpdateVertices)->ArgsProduct({{5, 6}, {1, 2}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Neighbourhoods)->ArgsProduct({{5, 6}, {1, 2}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Topology)->Args({6})->Args({8})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Denoise20)->ArgsProduct({{6}, {1, 2}})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
