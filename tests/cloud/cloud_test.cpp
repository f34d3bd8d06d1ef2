#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "helpers.h"
#include "scanmesh/clean_cloud.h"
#include "scanmesh/errors.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/length.h"
#include "scanmesh/cloud_io.h"

using namespace scanmesh;

namespace {

PointCloud plane_cloud(int n, double h, double noise, unsigned seed) {
  PointCloud c;
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, noise);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) c.points.emplace_back(i * h, j * h, noise > 0 ? g(rng) : 0.0);
  c.width = static_cast<int>(c.points.size());
  return c;
}

PointCloud sphere_cloud(int n, unsigned seed) {
  PointCloud c;
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int i = 0; i < n; ++i) c.points.push_back(Vec3(g(rng), g(rng), g(rng)).normalized());
  c.width = n;
  return c;
}

class CloudIo : public test::TempDirTest {};

}  // namespace

TEST(Length, ParsesAllForms) {
  EXPECT_DOUBLE_EQ(parse_length("0.25", "x").resolve(2, 3, 10), 0.25);
  EXPECT_DOUBLE_EQ(parse_length("3*spacing", "x").resolve(2, 3, 10), 6.0);
  EXPECT_DOUBLE_EQ(parse_length("2*edge", "x").resolve(2, 3, 10), 6.0);
  EXPECT_DOUBLE_EQ(parse_length("5%", "x").resolve(2, 3, 10), 0.5);
  EXPECT_THROW(parse_length("three", "x"), UsageError);
  EXPECT_THROW(parse_length("2*furlong", "x"), UsageError);
  EXPECT_THROW(parse_length("-1", "x"), UsageError);
}

TEST(CloudStages, CopiesOfAPointAreMergedKeepingTheFirst) {
  // Unorganized: later copies go, with their normals and colours; -0 and +0 are one position; NaN stays.
  PointCloud c;
  const double nan = std::nan("");
  c.points = {{1, 2, 3}, {0, 0, 0}, {1, 2, 3}, {4, 5, 6}, {-0.0, 0, 0}, {nan, 0, 0}, {1, 2, 3}};
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    c.normals.emplace_back(0, 0, static_cast<double>(i));
    c.colours.push_back({static_cast<std::uint8_t>(i), 0, 0});
  }
  c.width = static_cast<int>(c.points.size());
  EXPECT_EQ(merge_copies(c), 3u);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c.points[0], Vec3(1, 2, 3));
  EXPECT_EQ(c.points[1], Vec3(0, 0, 0));
  EXPECT_EQ(c.points[2], Vec3(4, 5, 6));
  EXPECT_TRUE(std::isnan(c.points[3].x()));
  EXPECT_EQ(c.normals[2].z(), 3.0);  // the attributes of the points kept
  EXPECT_EQ(c.colours[3][0], 5);
  EXPECT_EQ(merge_copies(c), 0u);  // nothing left to merge

  // Organized: the grid stays, every pixel at a shared position becomes a hole (a marker, not a
  // measurement); a cloud without copies is left as it was.
  PointCloud g = plane_cloud(4, 1.0, 0.0, 1);
  g.width = 4, g.height = 4;
  const PointCloud before = g;
  EXPECT_EQ(merge_copies(g), 0u);
  EXPECT_EQ(g.points, before.points);
  g.points[9] = g.points[2];
  g.points[12] = g.points[2];
  EXPECT_EQ(merge_copies(g), 3u);
  EXPECT_EQ(g.size(), 16u);
  for (int i : {2, 9, 12}) EXPECT_TRUE(std::isnan(g.points[i].x())) << i;
  EXPECT_EQ(g.finite_count(), 13u);

  // Many copies of one position among many other points (buckets of the hash, and a large one).
  PointCloud m = plane_cloud(100, 0.1, 0.01, 7);
  const std::size_t n = m.size();
  for (int k = 0; k < 20000; ++k) m.points.push_back(m.points[123]);
  m.width = static_cast<int>(m.points.size());
  EXPECT_EQ(merge_copies(m), 20000u);
  EXPECT_EQ(m.size(), n);
}

TEST(CloudStages, SurfaceProblemsAreToldApart) {
  PointCloud line;
  for (int i = 0; i < 100; ++i) line.points.emplace_back(i, 2.0 * i, 0.0);
  line.width = 100;
  EXPECT_NE(surface_problem(line).find("all 100 points lie on one line"), std::string::npos);
  // A plane with two far glitches is a surface (outlier removal takes the glitches), and the origin of
  // the single-precision stages stays on the plane.
  PointCloud glitch = plane_cloud(20, 0.05, 0.001, 4);
  glitch.points.emplace_back(1e9, 0, 0);
  glitch.points.emplace_back(1e9, 1, 0);
  glitch.width = static_cast<int>(glitch.points.size());
  EXPECT_EQ(surface_problem(glitch), "");
  EXPECT_LT(local_origin(glitch.points).norm(), 2.0);
  // Without far points the origin is the box's centre, as it always was.
  const PointCloud plane = plane_cloud(20, 0.05, 0.0, 5);
  const Box box = finite_box(plane.points);
  EXPECT_EQ(local_origin(plane.points), Vec3(0.5 * (box.lo + box.hi)));
}

TEST(CloudStages, ScaleOfAGrid) {
  const PointCloud c = plane_cloud(10, 0.5, 0.0, 1);
  const CloudScale s = measure_scale(c);
  EXPECT_NEAR(s.spacing, 0.5, 1e-12);
  EXPECT_NEAR(s.diagonal, 4.5 * std::sqrt(2.0), 1e-12);
}

TEST(CloudStages, VoxelAveragesAndIsDeterministic) {
  PointCloud c = plane_cloud(20, 0.1, 0.0, 1);
  c.colours.assign(c.size(), {10, 20, 30});
  const CloudScale s = measure_scale(c);
  PointCloud a = c, b = c;
  voxel_downsample(a, VoxelOptions{Length::spacings(2.0)}, s);
  voxel_downsample(b, VoxelOptions{Length::spacings(2.0)}, s);
  EXPECT_EQ(a.points, b.points);
  EXPECT_LE(a.size(), 121u);
  EXPECT_GE(a.size(), 100u);
  ASSERT_EQ(a.colours.size(), a.size());
  EXPECT_EQ(a.colours[0][1], 20);
}

TEST(CloudStages, VoxelMaxPointsBringsACloudWithinTheCount) {
  // A plane stays a plane (centroids of coplanar points), a sphere stays near the sphere; the count lands
  // at or below the limit and within 10% of it; the same input gives the same output.
  PointCloud plane = plane_cloud(100, 0.01, 0.0, 1);
  VoxelOptions o;
  o.max_points = 1000;
  PointCloud a = plane;
  const VoxelReport r = voxel_downsample(a, o, measure_scale(plane));
  EXPECT_EQ(r.before, 10000u);
  EXPECT_EQ(r.after, a.size());
  EXPECT_LE(a.size(), 1000u);
  EXPECT_GE(a.size(), 900u);
  EXPECT_GT(r.leaf, 0.02);
  for (const Vec3& p : a.points) EXPECT_EQ(p.z(), 0.0);
  PointCloud b = plane;
  voxel_downsample(b, o, measure_scale(plane));
  EXPECT_EQ(a.points, b.points);

  PointCloud sphere = sphere_cloud(20000, 5);
  o.max_points = 2000;
  const VoxelReport rs = voxel_downsample(sphere, o, measure_scale(sphere));
  EXPECT_LE(sphere.size(), 2000u);
  EXPECT_GE(sphere.size(), 1800u);
  EXPECT_EQ(rs.after, sphere.size());
  for (const Vec3& p : sphere.points) EXPECT_NEAR(p.norm(), 1.0, 0.02);

  // With an edge given as well, the limit only ever makes it larger.
  PointCloud c = plane;
  o.leaf = Length::spacings(1.5);
  o.max_points = 1000000;
  EXPECT_NEAR(voxel_downsample(c, o, measure_scale(plane)).leaf, 0.015, 1e-12);
  c = plane;
  o.max_points = 500;
  voxel_downsample(c, o, measure_scale(plane));
  EXPECT_LE(c.size(), 500u);
  EXPECT_GE(c.size(), 450u);
}

TEST(CloudStages, VoxelMaxPointsLeavesSmallAndOrganizedCloudsWhole) {
  PointCloud small = plane_cloud(20, 0.1, 0.0, 1);
  VoxelOptions o;
  o.max_points = 400;
  PointCloud s = small;
  VoxelReport r = voxel_downsample(s, o, measure_scale(small));
  EXPECT_EQ(s.points, small.points);
  EXPECT_EQ(r.leaf, 0.0);
  // A 30 x 30 grid over the limit stays whole: organized meshing needs the grid and is linear in it.
  PointCloud grid = plane_cloud(30, 0.1, 0.0, 1);
  grid.width = grid.height = 30;
  PointCloud g = grid;
  r = voxel_downsample(g, o, measure_scale(grid));
  EXPECT_TRUE(r.limit_skipped_organized);
  EXPECT_EQ(g.points, grid.points);
  EXPECT_TRUE(g.organized());
  // A limit of one still ends (at most 8 voxels meet at the origin's corner).
  PointCloud around = plane_cloud(10, 0.1, 0.0, 1);
  for (Vec3& p : around.points) p -= Vec3(0.45, 0.45, 0.0);
  o.max_points = 1;
  voxel_downsample(around, o, measure_scale(around));
  EXPECT_LE(around.size(), 8u);
}

TEST(CloudStages, OutliersAreRemovedFromAPlane) {
  PointCloud c = plane_cloud(30, 0.1, 0.002, 3);
  const std::size_t inliers = c.size();
  c.points.emplace_back(1.5, 1.5, 2.0);
  c.points.emplace_back(-3.0, 0.5, 0.3);
  c.width = static_cast<int>(c.size());
  remove_outliers(c, OutlierOptions{}, measure_scale(c));
  EXPECT_GE(c.size(), inliers - 5);
  for (const auto& p : c.points) EXPECT_LT(std::abs(p.z()), 0.1);
}

TEST(CloudStages, OrganizedCloudKeepsItsGridWithHoles) {
  PointCloud c = plane_cloud(16, 0.1, 0.0, 1);
  c.width = 16;
  c.height = 16;
  c.points[5] = Vec3::Constant(std::nan(""));
  c.points[40] = Vec3(0.4, 0.4, 5.0);  // a spike
  remove_outliers(c, OutlierOptions{}, measure_scale(c));
  EXPECT_EQ(c.size(), 256u);
  EXPECT_TRUE(c.organized());
  EXPECT_FALSE(c.points[5].allFinite());
  EXPECT_FALSE(c.points[40].allFinite());
}

TEST(CloudStages, NormalsOfAPlaneAndOutwardOnASphere) {
  PointCloud plane = plane_cloud(15, 0.1, 0.0, 1);
  estimate_normals(plane, NormalOptions{});
  for (const auto& n : plane.normals) EXPECT_NEAR(n.z(), 1.0, 1e-6);  // oriented up from the highest point
  PointCloud sphere = sphere_cloud(3000, 2);
  estimate_normals(sphere, NormalOptions{});
  std::size_t outward = 0;
  for (std::size_t i = 0; i < sphere.size(); ++i) outward += sphere.normals[i].dot(sphere.points[i]) > 0.9 ? 1 : 0;
  EXPECT_EQ(outward, sphere.size());
}

TEST(CloudStages, NormalsFaceTheSensor) {
  PointCloud plane = plane_cloud(15, 0.1, 0.0, 1);
  plane.sensor_origin = Vec3(0.7, 0.7, -5.0);
  estimate_normals(plane, NormalOptions{});
  for (const auto& n : plane.normals) EXPECT_NEAR(n.z(), -1.0, 1e-6);
}

TEST(CloudStages, StoredNormalsOrientTheEstimatedOnes) {
  // Both faces of a thin plate: propagation over the k-NN graph cannot tell the two sides apart, the
  // stored (scanner) normals can.
  PointCloud c;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j)
      for (double z : {0.0, 0.02}) {
        c.points.emplace_back(0.05 * i, 0.05 * j, z);
        c.normals.emplace_back(0.3, 0.0, z > 0 ? 1.0 : -1.0);  // rough, but on the right side
      }
  c.width = static_cast<int>(c.size());
  NormalOptions o;
  o.neighbours = 8;
  estimate_normals(c, o);
  for (std::size_t i = 0; i < c.size(); ++i) EXPECT_GT(c.normals[i].z() * (c.points[i].z() > 0.01 ? 1.0 : -1.0), 0.9) << i;
}

TEST(CloudStages, CubeCornerNormalsAreAxisAligned) {
  PointCloud c;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      c.points.emplace_back(0.0, 0.05 + 0.1 * i, 0.05 + 0.1 * j);
      c.points.emplace_back(0.05 + 0.1 * i, 0.0, 0.05 + 0.1 * j);
      c.points.emplace_back(0.05 + 0.1 * i, 0.05 + 0.1 * j, 0.0);
    }
  c.width = static_cast<int>(c.size());
  NormalOptions o;
  o.neighbours = 8;
  estimate_normals(c, o);
  std::size_t axis = 0;
  for (const auto& n : c.normals) axis += n.cwiseAbs().maxCoeff() > 0.99 ? 1 : 0;
  EXPECT_GT(axis, c.size() * 8 / 10);  // all but the points next to the corner's edges
}

TEST_F(CloudIo, XyzPcdAndPlyClouds) {
  const PointCloud xyz = read_cloud(write("a.xyz", "0 0 0\n1 0 0\n0 1 0\n# comment\n1 1 0.5\n"));
  EXPECT_EQ(xyz.size(), 4u);
  EXPECT_FALSE(xyz.has_normals());
  const PointCloud xyzn = read_cloud(write("b.xyz", "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n"));
  ASSERT_TRUE(xyzn.has_normals());
  EXPECT_EQ(xyzn.normals[2], Vec3(0, 0, 1));
  const PointCloud pcd = read_cloud(write("c.pcd", "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                                                 "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n0 0 0\n1 0 0\nnan nan nan\n"));
  EXPECT_EQ(pcd.size(), 2u);  // NaN dropped from an unorganized cloud
  const PointCloud organized = read_cloud(write("d.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                                                         "WIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
                                                         "0 0 1\nnan nan nan\n0 1 1\n1 1 1\n"));
  EXPECT_EQ(organized.size(), 4u);  // kept as a hole in an organized cloud
  EXPECT_TRUE(organized.organized());
  EXPECT_FALSE(organized.points[1].allFinite());
  ASSERT_TRUE(organized.sensor_origin.has_value());
  PointCloud w = xyzn;
  write_cloud_ply(w, path("e.ply"));
  const PointCloud back = read_cloud(path("e.ply"));
  EXPECT_EQ(back.points, w.points);
  EXPECT_EQ(back.normals, w.normals);
}

TEST_F(CloudIo, CloudFilesAreTheBytesOfEncodeCloud) {
  // 100k points with normals (a few megabytes of PLY): written through the streamed path, each file is
  // exactly what encode_cloud returns, and reads back to the same points.
  PointCloud c;
  for (int i = 0; i < 100000; ++i) {
    c.points.emplace_back(0.001 * (i % 317), 0.002 * (i / 317), std::sin(0.01 * i));
    c.normals.emplace_back(0.0, 0.0, 1.0);
  }
  c.width = static_cast<int>(c.size());
  write_cloud_ply(c, path("s.ply"));
  write_cloud_pcd(c, path("s.pcd"));
  EXPECT_EQ(read_file(path("s.ply")), encode_cloud(c, ".ply"));
  EXPECT_EQ(read_file(path("s.pcd")), encode_cloud(c, ".pcd"));
  EXPECT_EQ(read_cloud(path("s.ply")).points, c.points);
}

// PCD stores floats, which would round a georeferenced cloud (UTM: 4e6 m north) to decimetres: such a cloud
// is written with x y z as doubles and reads back exactly; a cloud near the origin keeps PCL's floats.
TEST_F(CloudIo, PcdKeepsGeoreferencedCoordinates) {
  PointCloud far = plane_cloud(12, 0.1, 0.01, 5);
  for (Vec3& p : far.points) p += Vec3(512345.678, 4123456.789, 251.5);
  far.normals.assign(far.size(), Vec3(0, 0.6, 0.8));
  far.sensor_origin = Vec3(512340.125, 4123450.0625, 300.5);
  write_cloud_pcd(far, path("far.pcd"));
  EXPECT_NE(read_file(path("far.pcd")).find("\nSIZE 8 8 8 4 4 4\n"), std::string::npos);
  const PointCloud back = read_cloud(path("far.pcd"));
  EXPECT_EQ(back.points, far.points);
  ASSERT_TRUE(back.sensor_origin.has_value());
  EXPECT_EQ(*back.sensor_origin, *far.sensor_origin);
  EXPECT_EQ(back.normals.size(), far.size());
  PointCloud near = plane_cloud(12, 0.1, 0.01, 5);
  write_cloud_pcd(near, path("near.pcd"));
  EXPECT_NE(read_file(path("near.pcd")).find("\nSIZE 4 4 4\n"), std::string::npos);
}

TEST_F(CloudIo, BadCloudsGiveClearErrors) {
  auto expect_error = [&](const std::string& file, const std::string& needle) {
    try {
      read_cloud(file);
      ADD_FAILURE() << "no error for " << file;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(std::filesystem::path(file).filename().string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(needle), std::string::npos) << "'" << needle << "' not in: " << msg;
    }
  };
  const std::string header = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 100\nHEIGHT 1\nPOINTS 100\n";
  expect_error(write("empty.pcd", ""), "empty");
  expect_error(write("zero.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 0\nHEIGHT 1\nPOINTS 0\nDATA ascii\n"), "empty");
  expect_error(write("nan.xyz", "nan nan nan\nnan 0 0\n"), "no point with finite coordinates");
  expect_error(write("header.pcd", "HELLO 1\n" + header + "DATA ascii\n"), "not a PCD file");
  expect_error(write("truncated.pcd", header + "DATA binary\n" + std::string(100, '\0')), "truncated");
  expect_error(write("columns.xyz", "0 0 0\n1 0\n"), "columns");
  expect_error(write("words.xyz", "0 0 zero\n"), "not a number");
  expect_error(write("cloud.las", "LASF"), "pdal translate");
  expect_error(write("cloud.e57", "ASTM"), "not supported");
  expect_error(write("cloud.obj", "v 0 0 0\n"), "unknown point-cloud format");
  expect_error(path("missing.pcd"), "No such file");
}

TEST_F(CloudIo, ReadersSurviveMutatedFiles) {
  // Truncated and corrupted clouds: a valid cloud or an InputError, never a crash or another exception.
  PointCloud c = plane_cloud(12, 0.1, 0.01, 5);
  c.normals.assign(c.size(), Vec3(0, 0, 1));
  write_cloud_pcd(c, path("valid.pcd"));  // binary_compressed
  write_cloud_ply(c, path("valid.ply"));
  const std::string ascii_pcd = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nPOINTS 3\nDATA ascii\n"
                                "0 0 0\n1 0 0\n0 1 0.5\n";
  const std::vector<std::pair<std::string, std::string>> valid = {
      {".pcd", scanmesh::read_file(path("valid.pcd"))}, {".ply", scanmesh::read_file(path("valid.ply"))},
      {".pcd", ascii_pcd}, {".xyz", "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n"}};
  std::mt19937 rng(17);
  for (const auto& [ext, bytes0] : valid)
    for (int round = 0; round < 120; ++round) {
      std::string bytes = bytes0;
      if (round % 2 == 0) bytes.resize(std::uniform_int_distribution<std::size_t>(0, bytes.size())(rng));
      else
        for (int k = 0; k < 4; ++k) bytes[std::uniform_int_distribution<std::size_t>(0, bytes.size() - 1)(rng)] = static_cast<char>(rng());
      const std::string file = write("fuzz" + ext, bytes);
      try {
        read_cloud(file);
      } catch (const InputError&) {
      } catch (const std::exception& e) {
        ADD_FAILURE() << ext << " round " << round << ": unexpected exception " << e.what();
      }
    }
}
