// The benches' peer (bench/peers.h) is only a yardstick, but the tables report against it: it must
// smooth, and keep what a smoother has to keep.
#include <gtest/gtest.h>

#include "helpers.h"
#include "peers.h"
#include "scanmesh/add_noise.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/topology.h"

using namespace scanmesh;

TEST(BilaplacianPeer, APlaneStaysExactlyPlanarAndItsBoundaryStays) {
  Mesh m = test::make_grid(12);
  const Mesh before = m;
  bench::bilaplacian_smooth(m, bench::kBilaplacianIterations);
  const Topology topo = build_topology(before);
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    EXPECT_EQ(m.positions[v].z(), 0.0) << v;
    if (topo.boundary_vertex[v]) {
      EXPECT_EQ(m.positions[v], before.positions[v]) << v;
    }
  }
}

TEST(BilaplacianPeer, LowersTheNormalErrorOfANoisySphere) {
  const Mesh clean = test::make_sphere(4);
  Mesh noisy = clean;
  NoiseOptions o;
  o.level = 0.3;
  add_noise(noisy, o);
  Mesh smoothed = noisy;
  bench::bilaplacian_smooth(smoothed, bench::kBilaplacianIterations);
  const double before = evaluate(noisy, &clean).msae_deg, after = evaluate(smoothed, &clean).msae_deg;
  EXPECT_LT(after, 0.5 * before) << before << " -> " << after;
}
