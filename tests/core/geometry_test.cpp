#include "scanmesh/geometry.h"
#include "scanmesh/point_cloud.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

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

TEST(PointCloudShape, OnePositionAndOneLineHaveNoSurface) {
  scanmesh::PointCloud c;
  c.points.assign(1000, scanmesh::Vec3(1, 2, 3));
  EXPECT_NE(scanmesh::surface_problem(c).find("all 1000 points are at one position"), std::string::npos);
  for (int i = 0; i < 1000; ++i) c.points[i] = scanmesh::Vec3(0.1 * i, 0.2 * i + 1, -0.3 * i);
  EXPECT_NE(scanmesh::surface_problem(c).find("lie on one line"), std::string::npos);
  // The same line rounded to single precision, as PCL's stages hand points back: still one line.
  for (auto& p : c.points) p = p.cast<float>().cast<double>();
  EXPECT_NE(scanmesh::surface_problem(c).find("lie on one line"), std::string::npos);
  // Every other point 1 mm off the line (the line is 37 long): a thin ribbon, a surface however narrow.
  for (std::size_t i = 0; i < c.points.size(); i += 2) c.points[i] += scanmesh::Vec3(0, 1e-3, 0);
  EXPECT_EQ(scanmesh::surface_problem(c), "");
  // A surface 1e-28 across: no single-precision stage can estimate its normals; the message says why.
  for (std::size_t i = 0; i < c.points.size(); ++i) c.points[i] = scanmesh::Vec3(1e-30 * (i % 30), 1e-30 * (i / 30), 1e-32 * (i % 7));
  EXPECT_NE(scanmesh::surface_problem(c).find("too little for the cloud stages"), std::string::npos) << scanmesh::surface_problem(c);
  c.points.assign(3, scanmesh::Vec3(std::nan(""), 0, 0));
  EXPECT_NE(scanmesh::surface_problem(c).find("no finite points"), std::string::npos);
}

TEST(PointCloud, LocalOriginIsTheCentreOfTheFinitePointsBox) {
  using scanmesh::Vec3;
  const double nan = std::nan("");
  EXPECT_EQ(scanmesh::local_origin({}), Vec3::Zero());
  EXPECT_EQ(scanmesh::local_origin({Vec3(nan, 0, 0)}), Vec3::Zero());
  const std::vector<Vec3> pts = {Vec3(512340.0, 4123450.0, 250.0), Vec3(nan, 1e9, 0), Vec3(512350.0, 4123470.0, 251.0),
                                 Vec3(512345.0, 4123460.0, 254.0)};
  EXPECT_EQ(scanmesh::local_origin(pts), Vec3(512345.0, 4123460.0, 252.0));
}

TEST(PointCloudShape, FirstCopiesNameTheLowestIndexAtEachPosition) {
  // Points at 50 positions, each repeated up to 400 times in shuffled order, plus NaN and -0/+0: every
  // point's first copy is the lowest index at its position, whatever the thread count.
  std::mt19937 rng(4);
  std::vector<Vec3> pts;
  for (int k = 0; k < 20000; ++k) pts.emplace_back(static_cast<double>(rng() % 50), 1.0, 2.0);
  pts.emplace_back(std::nan(""), 0.0, 0.0);
  pts.emplace_back(std::nan(""), 0.0, 0.0);
  pts.emplace_back(-0.0, 0.0, 0.0);
  pts.emplace_back(0.0, -0.0, 0.0);
  for (int threads : {1, 2}) {
    set_thread_count(threads);
    const std::vector<std::uint32_t> first = first_copies(pts);
    ASSERT_EQ(first.size(), pts.size());
    std::map<double, std::uint32_t> lowest;
    for (std::size_t i = 0; i < 20000; ++i) {
      lowest.emplace(pts[i].x(), static_cast<std::uint32_t>(i));
      EXPECT_EQ(first[i], lowest.at(pts[i].x())) << i;
    }
    EXPECT_EQ(first[20000], 20000u);  // NaN is never a copy
    EXPECT_EQ(first[20001], 20001u);
    EXPECT_EQ(first[20003], 20002u);  // -0 and +0 are one position
  }
  set_thread_count(0);
  EXPECT_TRUE(first_copies({Vec3(1, 2, 3), Vec3(1, 2, 4)}).empty());
  EXPECT_TRUE(first_copies({}).empty());
}
