#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "helpers.h"
#include "scanmesh/clean_cloud.h"
#include "scanmesh/clean_mesh.h"
#include "scanmesh/closest_point.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/geometry.h"
#include "scanmesh/errors.h"
#include "scanmesh/mesh_cloud.h"
#include "scanmesh/triangulate.h"

using namespace scanmesh;

namespace {

PointCloud sampled_sphere(int n) {
  PointCloud c;
  // Fibonacci sphere: even spacing, deterministic.
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z);
    c.points.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  c.width = n;
  return c;
}

void expect_clean(const Mesh& m) {
  const TopologyStats t = topology_stats(m);
  EXPECT_EQ(t.nonmanifold_edges, 0u);
  EXPECT_EQ(t.inconsistent_edges, 0u);
  EXPECT_EQ(t.degenerate_faces, 0u);
  EXPECT_EQ(t.nonfinite_vertices, 0u);
}

// A curved sheet of no thickness scanned from above and below: every spot is sampled twice, with the
// normals facing each sensor, i.e. opposite ways.
Vec3 sheet_normal(double x, double y) {
  return Vec3(-0.3 * std::cos(2.0 * x) * std::cos(2.0 * y), 0.3 * std::sin(2.0 * x) * std::sin(2.0 * y), 1.0).normalized();
}

PointCloud two_sided_sheet() {
  PointCloud c;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (int i = 0; i < 1200; ++i) {
    const double x = u(rng), y = u(rng);
    for (const double side : {1.0, -1.0}) {
      const Vec3 n = sheet_normal(x, y);
      c.points.push_back(Vec3(x, y, 0.15 * std::sin(2.0 * x) * std::cos(2.0 * y)) + noise(rng) * n);
      c.normals.push_back(side * n);
    }
  }
  c.width = static_cast<int>(c.size());
  return c;
}

}  // namespace

TEST(Meshing, Gp3OnASphereKeepsThePointsAndFacesOutwards) {
  PointCloud c = sampled_sphere(4000);
  estimate_normals(c, NormalOptions{});
  const CloudScale s = measure_scale(c);
  Mesh m = triangulate_gp3(c, Gp3Options{}, s);
  clean_mesh(m, CleanupOptions{});
  expect_clean(m);
  EXPECT_GT(m.num_faces(), 7000u);
  for (const auto& p : m.positions) EXPECT_NEAR(p.norm(), 1.0, 1e-6);  // measured points kept as vertices
  EXPECT_GT(signed_volume(m), 3.5);  // outward: close to 4/3 pi
}

// A cloud saved twice (every point copied): the spacing is still the distance between distinct points,
// and greedy projection meshes the distinct points as it meshes the cloud saved once.
TEST(Meshing, Gp3OnACloudWhosePointsAreAllCopiedMeshesTheDistinctPoints) {
  PointCloud once = sampled_sphere(2000);
  estimate_normals(once, NormalOptions{});
  PointCloud twice = once;
  twice.points.insert(twice.points.end(), once.points.begin(), once.points.end());
  twice.normals.insert(twice.normals.end(), once.normals.begin(), once.normals.end());
  twice.width = static_cast<int>(twice.size());
  const CloudScale s1 = measure_scale(once), s2 = measure_scale(twice);
  EXPECT_NEAR(s2.spacing, s1.spacing, 1e-12);
  const Mesh a = triangulate_gp3(once, Gp3Options{}, s1);
  const Mesh b = triangulate_gp3(twice, Gp3Options{}, s2);
  EXPECT_GT(a.num_faces(), 3500u);
  EXPECT_EQ(b.positions, a.positions);
  EXPECT_EQ(b.faces, a.faces);
}

// Too few usable normals: the error says how many points had one and why a normal can be missing.
TEST(Meshing, ACloudWithoutThreeUsableNormalsIsRefusedWithTheCount) {
  PointCloud c = sampled_sphere(50);
  estimate_normals(c, NormalOptions{});
  for (std::size_t i = 2; i < c.size(); ++i) c.normals[i] = Vec3::Zero();  // as when no plane could be fitted
  const CloudScale s = measure_scale(c);
  try {
    triangulate_gp3(c, Gp3Options{}, s);
    FAIL() << "meshed a cloud with two usable normals";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2 of the 50 points have a usable normal"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("normal_neighbours"), std::string::npos) << e.what();
  }
}

TEST(Meshing, OrganizedGridWithHoles) {
  PointCloud c;
  c.width = 20;
  c.height = 15;
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i) c.points.emplace_back(0.01 * i, 0.01 * j, 1.0);
  for (int k : {105, 106, 125, 126, 252}) c.points[k] = Vec3::Constant(std::nan(""));
  c.sensor_origin = Vec3::Zero();
  Mesh m = triangulate_organized(c, OrganizedOptions{}, measure_scale(c));
  clean_mesh(m, CleanupOptions{}, c.sensor_origin);
  expect_clean(m);
  EXPECT_EQ(m.num_vertices(), 295u);
  EXPECT_GT(m.num_faces(), 480u);
  for (const Face& f : m.faces) {  // facing the sensor at the origin, i.e. -z
    const Vec3 n = (m.positions[f[1]] - m.positions[f[0]]).cross(m.positions[f[2]] - m.positions[f[0]]);
    EXPECT_LT(n.z(), 0.0);
  }
  EXPECT_EQ(topology_stats(m).boundary_loops, 3u);  // the outline, the 2x2 hole and the single hole
}

// Georeferenced scans (UTM: 5e5 m east, 4e6 m north) mesh as they do at the origin. PCL holds points in
// single precision, whose step there is 0.03-0.5 m, so they go to it relative to a local origin.
// Coordinates on a grid of 2^-12 and an offset of powers of two make adding the offset exact: the run
// at the offset must give the same normals and faces, and positions moved by the offset.
TEST(Meshing, AGeoreferencedCloudMeshesAsItDoesAtTheOrigin) {
  const Vec3 offset(524288.0, 4194304.0, 256.0);
  PointCloud here = sampled_sphere(3000);
  for (Vec3& p : here.points) p = (p * 4096.0).array().round() / 4096.0;
  PointCloud there = here;
  for (Vec3& p : there.points) p += offset;
  OutlierOptions strict;
  strict.std_ratio = 1.0;  // removes some points, the same ones wherever the cloud lies
  remove_outliers(here, strict, measure_scale(here));
  remove_outliers(there, strict, measure_scale(there));
  ASSERT_LT(here.size(), 3000u);
  ASSERT_EQ(there.size(), here.size());
  estimate_normals(here, NormalOptions{});
  estimate_normals(there, NormalOptions{});
  EXPECT_EQ(there.normals, here.normals);
  const Mesh a = triangulate_gp3(here, Gp3Options{}, measure_scale(here));
  const Mesh b = triangulate_gp3(there, Gp3Options{}, measure_scale(there));
  ASSERT_GT(a.num_faces(), 4000u);
  EXPECT_EQ(b.faces, a.faces);
  ASSERT_EQ(b.num_vertices(), a.num_vertices());
  for (std::size_t v = 0; v < a.num_vertices(); ++v) ASSERT_EQ(b.positions[v], a.positions[v] + offset) << v;
  // Poisson's vertices are new points: they come back at the offset.
  PoissonOptions po;
  po.watertight = true;
  const Mesh pa = triangulate_poisson(here, po, measure_scale(here));
  const Mesh pb = triangulate_poisson(there, po, measure_scale(there));
  ASSERT_GT(pa.num_faces(), 1000u);
  EXPECT_EQ(pb.faces, pa.faces);
  ASSERT_EQ(pb.num_vertices(), pa.num_vertices());
  double worst = 0.0;
  for (std::size_t v = 0; v < pa.num_vertices(); ++v) worst = std::max(worst, (pb.positions[v] - offset - pa.positions[v]).norm());
  EXPECT_LT(worst, 1e-9);
  // An organized grid and its sensor.
  PointCloud grid;
  grid.width = 20;
  grid.height = 15;
  for (int j = 0; j < grid.height; ++j)
    for (int i = 0; i < grid.width; ++i) grid.points.emplace_back(i / 128.0, j / 128.0, 1.0 + ((i * j) % 3) / 512.0);
  grid.sensor_origin = Vec3::Zero();
  PointCloud far_grid = grid;
  for (Vec3& p : far_grid.points) p += offset;
  far_grid.sensor_origin = offset;
  const Mesh ga = triangulate_organized(grid, OrganizedOptions{}, measure_scale(grid));
  const Mesh gb = triangulate_organized(far_grid, OrganizedOptions{}, measure_scale(far_grid));
  ASSERT_GT(ga.num_faces(), 400u);
  EXPECT_EQ(gb.faces, ga.faces);
}

TEST(Meshing, PoissonIsWatertightOnASphere) {
  PointCloud c = sampled_sphere(3000);
  estimate_normals(c, NormalOptions{});
  PoissonOptions o;
  o.depth = 6;
  o.watertight = true;
  Mesh m = triangulate_poisson(c, o, measure_scale(c));
  clean_mesh(m, CleanupOptions{});
  expect_clean(m);
  EXPECT_EQ(topology_stats(m).boundary_edges, 0u);
  EXPECT_NEAR(signed_volume(m), 4.0 / 3.0 * M_PI, 0.3);
}

TEST(Cleanup, RepairsAMessyMesh) {
  Mesh m = test::make_grid(4, 0.25);
  const std::size_t good = m.num_faces();
  m.faces.push_back(m.faces[3]);                 // duplicate
  m.faces.push_back({m.faces[5][0], m.faces[5][2], m.faces[5][1]});  // duplicate, flipped
  m.faces.push_back({1, 1, 2});                  // degenerate
  m.positions.emplace_back(0.25, 0.0, 1.0);      // a fin on the interior edge (0,6): non-manifold
  m.faces.push_back({0, 6, static_cast<int>(m.num_vertices()) - 1});
  m.positions.emplace_back(9, 9, 9);             // unreferenced
  for (std::size_t f = 0; f < good; f += 3) std::swap(m.faces[f][1], m.faces[f][2]);  // scrambled orientation
  const CleanupReport r = clean_mesh(m, CleanupOptions{});
  expect_clean(m);
  EXPECT_EQ(r.duplicate_faces, 2u);
  EXPECT_EQ(r.degenerate_faces, 1u);
  EXPECT_GE(r.nonmanifold_faces + r.small_component_faces, 1u);
  EXPECT_EQ(m.num_faces(), good);
  EXPECT_EQ(m.num_vertices(), 25u);
}

TEST(Cleanup, SplitsABowtieVertexAndOrientsClosedPiecesOutwards) {
  Mesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0)};
  m.faces = {{0, 1, 2}, {0, 3, 4}};  // two triangles touching at vertex 0 only
  CleanupOptions o;
  o.min_component_faces = 0;
  const CleanupReport r = clean_mesh(m, o);
  EXPECT_EQ(r.split_vertices, 1u);
  EXPECT_EQ(m.num_vertices(), 6u);
  Mesh cube = test::make_cube(2);
  for (auto& f : cube.faces) std::swap(f[1], f[2]);  // inside out
  clean_mesh(cube, CleanupOptions{});
  EXPECT_NEAR(signed_volume(cube), 1.0, 1e-12);
}

// A Moebius band of n segments: every vertex on its one boundary, and no orientation fits it, so clean-up
// must remove a face, which leaves the corner between its two neighbours joining two fans.
Mesh moebius_band(int n) {
  Mesh m;
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * M_PI * i / n, half = 0.5 * t;
    const Vec3 centre(std::cos(t), std::sin(t), 0.0);
    const Vec3 across(std::cos(half) * std::cos(t), std::cos(half) * std::sin(t), std::sin(half));
    m.positions.push_back(centre + 0.3 * across);
    m.positions.push_back(centre - 0.3 * across);
  }
  for (int i = 0; i < n; ++i) {
    const int t0 = 2 * i, b0 = 2 * i + 1;
    // after the last segment the band comes back turned over: top meets bottom
    const int t1 = i + 1 < n ? 2 * (i + 1) : 1, b1 = i + 1 < n ? 2 * (i + 1) + 1 : 0;
    m.faces.push_back({t0, b0, b1});
    m.faces.push_back({t0, b1, t1});
  }
  return m;
}

TEST(Cleanup, WhatItHandsOnIsManifoldAtItsVerticesAfterRemovingFolds) {
  for (int n = 6; n <= 24; ++n) {
    Mesh m = moebius_band(n);
    CleanupOptions o;
    o.min_component_faces = 0;
    const CleanupReport r = clean_mesh(m, o);
    ASSERT_GE(r.fold_faces, 1u) << n << " segments: a Moebius band cannot be oriented whole";
    EXPECT_EQ(r.unorientable_edges, 0u) << n;
    // Clean-up again finds nothing to split: no vertex joins two fans.
    CleanupOptions again;
    again.min_component_faces = 0;
    EXPECT_EQ(clean_mesh(m, again).split_vertices, 0u) << n << " segments";
    EXPECT_EQ(topology_stats(m).inconsistent_edges, 0u) << n;
  }
}

TEST(MeshCloud, AutoKeepsGreedyProjectionWhereItCoversTheScan) {
  PointCloud c = sampled_sphere(4000);
  estimate_normals(c, NormalOptions{});
  MeshingDecision d;
  const Mesh m = mesh_cloud(c, MeshMethodOptions{}, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, measure_scale(c), &d);
  EXPECT_EQ(d.method, MeshMethod::gp3) << d.reason;
  EXPECT_EQ(m.num_vertices(), c.size());
  EXPECT_GE(d.fit.coverage, 0.99);
}

TEST(MeshCloud, AutoClosesAGapWithinItsTrimDistanceAndLeavesTheUnseenRegionOpen) {
  // A sphere scanned all round but for a cap the views missed (the rim of what was seen) and a spot six
  // spacings across without points, which greedy projection leaves open (a gap: the probe at its centre
  // finds no point within 1.5 spacings). The spot's patch reaches 3 spacings from the points: beyond the
  // closing's default trim (1.5 spacings), so it stays open, and within a trim of 4, which keeps it. The
  // unseen cap, far from every point, stays open either way.
  const PointCloud full = sampled_sphere(4000);
  const double spacing = std::sqrt(4.0 * M_PI / 4000.0);
  const Vec3 pole(0, 0, 1), spot = Vec3(1, 1, -0.3).normalized();
  PointCloud c;
  for (const Vec3& p : full.points)
    if ((p - pole).norm() > 0.6 && (p - spot).norm() > 3.0 * spacing) c.points.push_back(p);
  c.width = static_cast<int>(c.size());
  estimate_normals(c, NormalOptions{});
  const CloudScale s = measure_scale(c);
  auto loops = [](const MeshingDecision& d) {
    std::pair<std::size_t, std::size_t> rims_others{0, 0};
    for (const auto& loop : d.fit.loops) (loop.kind == BoundaryLoopFit::Kind::rim ? rims_others.first : rims_others.second) += 1;
    return rims_others;
  };
  MeshingDecision d;
  const Mesh m = mesh_cloud(c, MeshMethodOptions{}, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, s, &d);
  ASSERT_EQ(d.method, MeshMethod::gp3) << d.reason;  // an open gap does not count against greedy projection
  const ClosestPointIndex surface(m);
  EXPECT_GT(surface.closest(spot).distance, 0.5 * s.spacing) << d.reason;
  EXPECT_GT(surface.closest(pole).distance, 5.0 * s.spacing) << d.reason;
  EXPECT_EQ(loops(d), std::make_pair(std::size_t{1}, std::size_t{1})) << d.reason;  // the cap's rim and the spot, a gap
  MeshMethodOptions loose;
  loose.fill_trim = Length::spacings(4.0);
  MeshingDecision dl;
  const Mesh ml = mesh_cloud(c, loose, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, s, &dl);
  ASSERT_EQ(dl.method, MeshMethod::gp3) << dl.reason;
  const ClosestPointIndex loose_surface(ml);
  EXPECT_LT(loose_surface.closest(spot).distance, 0.5 * s.spacing) << dl.reason;  // closed (a flat patch on the sphere)
  EXPECT_GT(loose_surface.closest(pole).distance, 5.0 * s.spacing) << dl.reason;
  EXPECT_EQ(loops(dl), std::make_pair(std::size_t{1}, std::size_t{0})) << dl.reason;
  // Without closing, greedy projection leaves the spot open: the test above is about the closing.
  loose.fill_holes = false;
  const Mesh open = mesh_cloud(c, loose, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, s, nullptr);
  EXPECT_GT(ClosestPointIndex(open).closest(spot).distance, 0.5 * s.spacing);
}

TEST(MeshCloud, AOneSidedScansDropoutIsClosedWithItsOwnTrim) {
  // A single view of a gently curved sheet (normals towards the sensor above) with a round dropout 5.6
  // spacings across: one-sided, so the closing's patch may reach fill_trim_one_sided (3 spacings) from
  // the points, and the dropout is closed; with that trim at 2 spacings it stays open.
  PointCloud c;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  const Vec3 centre(20.0, 20.0, 0.0);
  auto height = [](double x, double y) { return 0.004 * ((x - 20) * (x - 20) + (y - 20) * (y - 20)); };
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 40; ++j) {
      const double x = i + jitter(rng), y = j + jitter(rng);
      if (std::hypot(x - centre.x(), y - centre.y()) <= 2.8) continue;
      c.points.emplace_back(x, y, height(x, y));
      c.normals.push_back(Vec3(-0.008 * (x - 20), -0.008 * (y - 20), 1.0).normalized());
    }
  c.width = static_cast<int>(c.size());
  const CloudScale s = measure_scale(c);
  const Vec3 middle(20.0, 20.0, 0.0);
  MeshingDecision d;
  const Mesh m = mesh_cloud(c, MeshMethodOptions{}, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, s, &d);
  ASSERT_EQ(d.method, MeshMethod::gp3) << d.reason;
  ASSERT_NE(d.reason.find("holes closed"), std::string::npos) << d.reason;
  EXPECT_LT(ClosestPointIndex(m).closest(middle).distance, 0.5 * s.spacing) << d.reason;
  MeshMethodOptions tight;
  tight.fill_trim_one_sided = Length::spacings(2.0);
  MeshingDecision dt;
  const Mesh mt = mesh_cloud(c, tight, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, s, &dt);
  ASSERT_EQ(dt.method, MeshMethod::gp3) << dt.reason;
  EXPECT_GT(ClosestPointIndex(mt).closest(middle).distance, 2.0 * s.spacing) << dt.reason;
  // fill_trim, for clouds seen from several sides, does not apply here.
  MeshMethodOptions other;
  other.fill_trim = Length::spacings(1.0);
  MeshingDecision dother;
  const Mesh mo = mesh_cloud(c, other, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, s, &dother);
  EXPECT_LT(ClosestPointIndex(mo).closest(middle).distance, 0.5 * s.spacing) << dother.reason;
}

TEST(MeshCloud, AutoTurnsToPoissonWhereGreedyProjectionLeavesHoles) {
  // A sparse, unevenly sampled sphere with its true normals (a complete object from a few views):
  // greedy projection leaves holes between the clusters; Poisson closes them.
  PointCloud c;
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int i = 0; i < 700; ++i) {
    Vec3 p(g(rng), g(rng), g(rng));
    p.normalize();
    c.points.push_back(p);
    c.normals.push_back(p);
  }
  c.width = static_cast<int>(c.size());
  MeshingDecision d;
  const CloudScale s = measure_scale(c);
  MeshMethodOptions keep_holes;
  keep_holes.fill_holes = false;
  const Mesh m = mesh_cloud(c, keep_holes, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, s, &d);
  // Whatever won represents the points at least as well as greedy projection alone.
  const ScanFit gp3 = measure_scan_fit(triangulate_gp3(c, Gp3Options{}, s), c.points, s.spacing);
  EXPECT_GE(d.fit.coverage, gp3.coverage);
  EXPECT_LE(d.fit.holes, gp3.holes);
  if (gp3.holes > 0) {
    EXPECT_EQ(d.method, MeshMethod::poisson) << d.reason;
  }
  EXPECT_FALSE(m.faces.empty());
  EXPECT_NE(d.reason.find("covers"), std::string::npos);

  // With greedy projection's holes closed first (the default), greedy projection is kept only when
  // nothing is left that would make it fall short, and then says how many holes it closed.
  MeshingDecision e;
  const Mesh closed = mesh_cloud(c, MeshMethodOptions{}, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, s, &e);
  EXPECT_FALSE(closed.faces.empty());
  EXPECT_GE(e.fit.coverage, gp3.coverage);
  if (e.method == MeshMethod::gp3) {
    const ScanFitLimits limits;
    EXPECT_GE(e.fit.coverage, limits.min_coverage) << e.reason;
    for (const auto& loop : e.fit.loops)
      EXPECT_FALSE(loop.kind == BoundaryLoopFit::Kind::hole && loop.perimeter >= limits.min_hole_perimeter * e.fit.spacing) << e.reason;
    if (gp3.holes > 0) {
      EXPECT_NE(e.reason.find("holes closed"), std::string::npos) << e.reason;
    }
  } else {
    EXPECT_EQ(e.method, MeshMethod::poisson) << e.reason;
  }
}

TEST(MeshCloud, ASheetSeenFromBothSidesIsMeshedAsOneLayer) {
  // Poisson on the sensors' normals wraps the sheet in two layers; mesh.auto must notice and give one.
  PointCloud c = two_sided_sheet();
  MeshingDecision d;
  const Mesh m = mesh_cloud(c, MeshMethodOptions{}, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, measure_scale(c), &d);
  ASSERT_FALSE(m.faces.empty());
  double opposed = -1.0;
  for (const auto& [name, value] : d.numbers)
    if (name == "opposed_normals") opposed = value;
  if (d.method == MeshMethod::poisson) {
    EXPECT_GT(opposed, 0.3) << d.reason;
  }
  // One layer: about the sheet's area (4.1; two layers would be twice that), faces turned one way.
  FaceGeometry g;
  compute_face_geometry(m.positions, m.faces, g);
  double area = 0.0, up = 0.0;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    area += g.areas[f];
    up += g.normals[f].dot(sheet_normal(g.centroids[f].x(), g.centroids[f].y())) > 0.0 ? g.areas[f] : 0.0;
  }
  EXPECT_LT(area, 1.4 * 4.1) << d.reason;
  EXPECT_TRUE(up / area > 0.9 || up / area < 0.1) << "share facing up " << up / area << "; " << d.reason;
}

TEST(Meshing, PoissonWritesNothingOnStdout) {
  // PCL's Poisson printf()s marching-cubes complaints; on the two-sided sheet it has many. Stdout is
  // the user's (--quiet, pipes): they must not reach it.
  const PointCloud c = two_sided_sheet();
  std::fflush(stdout);
  const int saved = ::dup(STDOUT_FILENO);
  std::FILE* capture = std::tmpfile();
  ASSERT_NE(capture, nullptr);
  ::dup2(::fileno(capture), STDOUT_FILENO);
  const Mesh m = triangulate_poisson(c, PoissonOptions{}, measure_scale(c));
  std::printf("after\n");  // stdout works again afterwards
  std::fflush(stdout);
  ::dup2(saved, STDOUT_FILENO);
  ::close(saved);
  std::rewind(capture);
  std::string written;
  for (int ch; (ch = std::fgetc(capture)) != EOF;) written.push_back(static_cast<char>(ch));
  std::fclose(capture);
  EXPECT_FALSE(m.faces.empty());
  EXPECT_EQ(written, "after\n");
}

TEST(MeshCloud, OrganizedCloudsAreMeshedOnTheirGrid) {
  PointCloud c;
  c.width = 30;
  c.height = 20;
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i) c.points.emplace_back(0.01 * i, 0.01 * j, 1.0);
  c.sensor_origin = Vec3(0.15, 0.1, 0.0);
  MeshingDecision d;
  const Mesh m = mesh_cloud(c, MeshMethodOptions{}, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, measure_scale(c), &d);
  EXPECT_EQ(d.method, MeshMethod::organized);
  EXPECT_EQ(m.num_faces(), 2u * 29u * 19u);
  MeshMethodOptions organized;
  organized.method = MeshMethod::organized;
  PointCloud list = c;
  list.width = static_cast<int>(list.size());
  list.height = 1;
  EXPECT_THROW(mesh_cloud(list, organized, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, measure_scale(list)), InputError);
}
