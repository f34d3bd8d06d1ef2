#include "scanmesh/evaluate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "helpers.h"
#include "scanmesh/closest_point.h"

using namespace scanmesh;

TEST(Metrics, QualityByHand) {
  Mesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, std::sqrt(3.0) / 2, 0), Vec3(0, 1, 0), Vec3(2, 0, 0)};
  m.faces = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}};  // equilateral, right isosceles, degenerate
  const MeshMetrics r = evaluate(m, nullptr);
  EXPECT_NEAR(r.face_quality[0], 1.0 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(r.face_quality[1], std::sqrt(2.0) / 2.0, 1e-12);  // circumradius = hypotenuse / 2
  EXPECT_TRUE(std::isinf(r.face_quality[2]));
  EXPECT_NEAR(r.quality_mean, (1.0 / std::sqrt(3.0) + std::sqrt(2.0) / 2.0) / 2.0, 1e-12);
  EXPECT_EQ(r.topology.degenerate_faces, 1u);
}

TEST(Metrics, MsaeAndFlipsByHand) {
  const Mesh ref = test::make_grid(1);  // two faces, normals +z
  Mesh m = ref;
  // Lift vertex 1, which only face 0 uses: face 0 tilts, face 1 keeps its normal.
  m.positions[1].z() = 0.5;
  const Face& f0 = m.faces[0];
  const Vec3 n0 = (m.positions[f0[1]] - m.positions[f0[0]]).cross(m.positions[f0[2]] - m.positions[f0[0]]).normalized();
  const double expected0 = std::acos(n0.z()) * 180.0 / M_PI;
  MeshMetrics r = evaluate(m, &ref);
  ASSERT_TRUE(r.same_connectivity);
  EXPECT_NEAR(r.face_angle_error[0], expected0, 1e-9);
  EXPECT_NEAR(r.face_angle_error[1], 0.0, 1e-9);
  EXPECT_NEAR(r.msae_deg, expected0 / 2.0, 1e-9);
  EXPECT_EQ(r.flipped_faces, 0u);
  // A mirrored copy has every normal reversed: a 180-degree error, two flips.
  Mesh flipped = ref;
  for (auto& p : flipped.positions) p.x() = -p.x();  // mirror: same faces, opposite normals
  r = evaluate(flipped, &ref);
  EXPECT_EQ(r.flipped_faces, 2u);
  EXPECT_NEAR(r.msae_deg, 180.0, 1e-9);
}

TEST(Metrics, DistancesOfAnOffsetPlane) {
  Mesh ref = test::make_grid(10, 0.1);  // [0,1]^2
  Mesh m = test::make_grid(4, 0.1);     // [0,0.4]^2, inside the reference
  for (auto& p : m.positions) p += Vec3(0.3, 0.3, 0.05);
  const MeshMetrics r = evaluate(m, &ref);
  EXPECT_FALSE(r.same_connectivity);
  EXPECT_NEAR(r.ev, 0.05, 1e-12);
  EXPECT_NEAR(r.ev_relative, 0.05 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(r.hausdorff_to_reference, 0.05, 1e-12);
  // From the reference's far corner (1,1,0) to the small plane's corner (0.7,0.7,0.05).
  EXPECT_NEAR(r.hausdorff_from_reference, std::sqrt(0.09 + 0.09 + 0.0025), 1e-12);
}

TEST(Metrics, EvMatchesBruteForce) {
  const Mesh ref = test::make_sphere(2);
  Mesh m = ref;
  std::mt19937 rng(2);
  std::normal_distribution<double> n(0.0, 0.02);
  for (auto& p : m.positions) p += Vec3(n(rng), n(rng), n(rng));
  const MeshMetrics r = evaluate(m, &ref);
  for (std::size_t v = 0; v < m.num_vertices(); ++v) {
    double best = 1e300;
    for (const Face& f : ref.faces)
      best = std::min(best, (closest_point_on_triangle(m.positions[v], ref.positions[f[0]], ref.positions[f[1]], ref.positions[f[2]]) -
                             m.positions[v]).norm());
    ASSERT_NEAR(r.vertex_distance[v], best, 1e-12) << v;
  }
}

TEST(Metrics, VolumeOfCubeAndChange) {
  const Mesh cube = test::make_cube(3);
  EXPECT_NEAR(signed_volume(cube), 1.0, 1e-12);
  Mesh big = cube;
  for (auto& p : big.positions) p *= 1.1;
  const MeshMetrics r = evaluate(big, &cube);
  ASSERT_TRUE(r.volume_change.has_value());
  EXPECT_NEAR(*r.volume_change, 0.331, 1e-9);
  EXPECT_EQ(r.topology.boundary_edges, 0u);
  EXPECT_EQ(r.topology.components, 1u);
}

TEST(Metrics, JsonHasTheNumbers) {
  const Mesh cube = test::make_cube(2);
  const std::string j = metrics_json(evaluate(cube, &cube));
  EXPECT_NE(j.find("\"msae_deg\": 0"), std::string::npos) << j;
  EXPECT_NE(j.find("\"flipped_faces\": 0"), std::string::npos);
  EXPECT_NE(j.find("\"volume_change\": 0"), std::string::npos);
}
