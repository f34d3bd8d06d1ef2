#include "scanmesh/geometry.h"

#include <gtest/gtest.h>

#include "helpers.h"
#include "scanmesh/parallel.h"

using namespace scanmesh;

TEST(Geometry, FaceNormalsAreasCentroids) {
  const Mesh m = test::make_grid(2, 0.5);
  FaceGeometry g;
  compute_face_geometry(m.positions, m.faces, g);
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    EXPECT_NEAR(g.normals[f].z(), 1.0, 1e-15);
    EXPECT_NEAR(g.areas[f], 0.125, 1e-15);
  }
  EXPECT_NEAR(g.centroids[0].x(), 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(g.centroids[0].y(), 1.0 / 6.0, 1e-15);
}

TEST(Geometry, DegenerateFaceHasZeroNormalAndArea) {
  double area = -1.0;
  const Vec3 n = triangle_normal(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2), &area);
  EXPECT_EQ(n, Vec3::Zero());
  EXPECT_EQ(area, 0.0);
}

TEST(Geometry, MeanEdgeLengthAndBBox) {
  const Mesh m = test::make_grid(1, 2.0);
  EXPECT_NEAR(mean_edge_length(m, build_topology(m)), (4 * 2.0 + 2.0 * std::sqrt(2.0)) / 5.0, 1e-12);
  EXPECT_NEAR(bbox_diagonal(m.positions), 2.0 * std::sqrt(2.0), 1e-12);
}

TEST(Geometry, VertexNormalsOfSpherePointOutwards) {
  const Mesh m = test::make_sphere(2);
  FaceGeometry g;
  compute_face_geometry(m.positions, m.faces, g);
  const auto n = vertex_normals(build_topology(m), g);
  for (std::size_t v = 0; v < m.num_vertices(); ++v) EXPECT_GT(n[v].dot(m.positions[v]), 0.99);
}
