// The tuning corpus's coarser versions of a dense model (bench/corpus.h, decimate): a closed surface stays a
// closed, consistently oriented surface of about the asked size, on the shape it had, the same every time.
#include <gtest/gtest.h>

#include "corpus.h"
#include "helpers.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/topology.h"

using namespace scanmesh;

TEST(CorpusDecimate, ASphereStaysAClosedSphereOfAboutTheAskedSize) {
  const Mesh dense = test::make_sphere(4);  // 5,120 faces
  const Mesh coarse = bench::decimate(dense, 1000);
  EXPECT_NEAR(static_cast<double>(coarse.num_faces()), 1000.0, 20.0);
  const Topology topo = build_topology(coarse);
  EXPECT_EQ(topo.num_boundary_edges(), 0u);
  EXPECT_EQ(topo.num_nonmanifold_edges(), 0u);
  EXPECT_EQ(topology_stats(coarse).inconsistent_edges, 0u);
  EXPECT_NEAR(signed_volume(coarse), signed_volume(dense), 0.03 * signed_volume(dense));  // outward, same size
  for (const Vec3& p : coarse.positions) EXPECT_NEAR(p.norm(), 1.0, 0.02);
  const Mesh again = bench::decimate(dense, 1000);
  EXPECT_EQ(again.positions, coarse.positions);
  EXPECT_EQ(again.faces, coarse.faces);
}
