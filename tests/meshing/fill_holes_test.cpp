#include "scanmesh/fill_holes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "helpers.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/parallel.h"
#include "scanmesh/scan_fit.h"

using namespace scanmesh;

namespace {

// The rings of the loops the scan fit calls holes, for a mesh cut from a grid whose vertices are the points.
// With `every_loop` also the rim (on a closed shape with one hole, that hole is the piece's longest loop).
std::vector<std::vector<int>> hole_rings(const Mesh& mesh, const std::vector<Vec3>& points, bool every_loop = false) {
  const ScanFit fit = measure_scan_fit(mesh, points, 1.0);
  std::vector<std::vector<int>> rings;
  for (const auto& l : fit.loops)
    if (every_loop || l.kind == BoundaryLoopFit::Kind::hole) rings.push_back(l.ring);
  return rings;
}

Mesh without_faces(const Mesh& m, const std::function<bool(const Vec3&)>& cut) {
  Mesh out = m;
  out.faces.clear();
  for (const Face& f : m.faces)
    if (!cut((m.positions[f[0]] + m.positions[f[1]] + m.positions[f[2]]) / 3.0)) out.faces.push_back(f);
  return out;
}

double total_area(const Mesh& m) {
  double a = 0.0;
  for (const Face& f : m.faces) a += 0.5 * (m.positions[f[1]] - m.positions[f[0]]).cross(m.positions[f[2]] - m.positions[f[0]]).norm();
  return a;
}

// The 6 x 6 grid without the unit squares at (2, 2) and (3, 3): two holes touching at vertex (3, 3).
Mesh two_touching_holes(const Mesh& grid) {
  return without_faces(grid, [](const Vec3& c) {
    return (c.x() > 2 && c.x() < 3 && c.y() > 2 && c.y() < 3) || (c.x() > 3 && c.x() < 4 && c.y() > 3 && c.y() < 4);
  });
}

// A grid closed again: its area, manifold, consistently oriented, only its rim open.
void expect_whole_grid(const Mesh& m, double area) {
  EXPECT_NEAR(total_area(m), area, 1e-9);
  const TopologyStats t = topology_stats(m);
  EXPECT_EQ(t.nonmanifold_edges, 0u);
  EXPECT_EQ(t.inconsistent_edges, 0u);
  EXPECT_EQ(t.boundary_loops, 1u);
}

double smallest_angle_deg(const Mesh& m, std::size_t first_face) {
  double smallest = 180.0;
  for (std::size_t f = first_face; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = m.positions[m.faces[f][k]];
      const Vec3 a = m.positions[m.faces[f][(k + 1) % 3]] - p, b = m.positions[m.faces[f][(k + 2) % 3]] - p;
      smallest = std::min(smallest, std::acos(std::clamp(a.dot(b) / (a.norm() * b.norm()), -1.0, 1.0)) * 180.0 / M_PI);
    }
  return smallest;
}

}  // namespace

TEST(FillHoles, AHoleInAPlaneIsClosedFlatWellShapedAndFacingTheSameWay) {
  const Mesh grid = test::make_grid(20);
  Mesh m = without_faces(grid, [](const Vec3& c) { return (c - Vec3(10, 10, 0)).norm() < 4.5; });
  ASSERT_LT(m.num_faces(), grid.num_faces() - 100);
  const auto rings = hole_rings(m, grid.positions);
  ASSERT_EQ(rings.size(), 1u);
  const std::size_t faces_before = m.num_faces();
  const auto patches = fill_holes(m, rings);
  ASSERT_TRUE(patches[0].filled);
  EXPECT_GT(patches[0].vertices, 0u) << "a hole 9 edges across needs vertices inside";
  // The plane is whole again: same area, every face facing +z, every new vertex in the plane.
  EXPECT_NEAR(total_area(m), 400.0, 1e-9);
  for (const Face& f : m.faces) EXPECT_GT((m.positions[f[1]] - m.positions[f[0]]).cross(m.positions[f[2]] - m.positions[f[0]]).z(), 0.0);
  for (std::size_t v = patches[0].first_vertex; v < m.num_vertices(); ++v) EXPECT_EQ(m.positions[v].z(), 0.0);
  const TopologyStats t = topology_stats(m);
  EXPECT_EQ(t.nonmanifold_edges, 0u);
  EXPECT_EQ(t.inconsistent_edges, 0u);
  EXPECT_EQ(t.boundary_loops, 1u) << "only the grid's rim";
  // No slivers: the patch's smallest angle.
  EXPECT_GT(smallest_angle_deg(m, faces_before), 20.0);
}

TEST(FillHoles, LoopsThroughOnePinchVertexAreClosedWithoutRepeatingAnEdge) {
  // Two square holes touching at the grid vertex (3, 3).
  const Mesh grid = test::make_grid(6);
  Mesh m = two_touching_holes(grid);
  const auto rings = hole_rings(m, grid.positions);
  ASSERT_EQ(rings.size(), 2u);
  const auto patches = fill_holes(m, rings);
  for (const auto& p : patches) EXPECT_TRUE(p.filled);
  expect_whole_grid(m, 36.0);
}

TEST(FillHoles, ALoopPassingAVertexTwiceIsClosedAsItsTwoParts) {
  // The same two holes walked as one figure-eight loop through the pinch vertex.
  const Mesh grid = test::make_grid(6);
  Mesh m = two_touching_holes(grid);
  auto rings = hole_rings(m, grid.positions);
  ASSERT_EQ(rings.size(), 2u);
  const int pinch = 3 * 7 + 3;
  std::vector<int> eight;
  for (auto& r : rings) {
    const auto at = std::find(r.begin(), r.end(), pinch);
    ASSERT_NE(at, r.end());
    std::rotate(r.begin(), at, r.end());
    eight.insert(eight.end(), r.begin(), r.end());
  }
  const auto patches = fill_holes(m, {eight});
  ASSERT_TRUE(patches[0].filled);
  expect_whole_grid(m, 36.0);
}

TEST(FillHoles, AHoleOnACubeFaceClosesInThatFaceAndTheCubeIsClosedAgain) {
  const Mesh cube = test::make_cube(8);
  Mesh m = without_faces(cube, [](const Vec3& c) { return c.z() > 1 - 1e-9 && (c - Vec3(0.5, 0.5, 1)).norm() < 0.3; });
  const auto rings = hole_rings(m, cube.positions, true);
  ASSERT_EQ(rings.size(), 1u);
  const auto patches = fill_holes(m, rings);
  ASSERT_TRUE(patches[0].filled);
  for (std::size_t v = patches[0].first_vertex; v < m.num_vertices(); ++v) EXPECT_NEAR(m.positions[v].z(), 1.0, 1e-12);
  for (std::size_t f = patches[0].first_face; f < m.num_faces(); ++f) {
    const Face& g = m.faces[f];
    EXPECT_GT((m.positions[g[1]] - m.positions[g[0]]).cross(m.positions[g[2]] - m.positions[g[0]]).z(), 0.0) << "outwards, like the cube";
  }
  EXPECT_NEAR(total_area(m), 6.0, 1e-9);
  const TopologyStats t = topology_stats(m);
  EXPECT_EQ(t.boundary_edges, 0u);
  EXPECT_EQ(t.inconsistent_edges, 0u);
}

TEST(FillHoles, RemovingThePatchesGivesTheMeshBack) {
  const Mesh grid = test::make_grid(20);
  const Mesh holed = without_faces(grid, [](const Vec3& c) { return (c - Vec3(5, 5, 0)).norm() < 2.5 || (c - Vec3(14, 14, 0)).norm() < 3.5; });
  Mesh m = holed;
  const auto rings = hole_rings(m, grid.positions);
  ASSERT_EQ(rings.size(), 2u);
  auto patches = fill_holes(m, rings);
  ASSERT_GT(m.num_faces(), holed.num_faces());
  // Remove the first patch only: the second keeps its faces, renumbered.
  remove_patches(m, patches, {0, 1});
  EXPECT_FALSE(patches[0].filled);
  ASSERT_TRUE(patches[1].filled);
  EXPECT_EQ(patches[1].first_face, holed.num_faces());
  EXPECT_EQ(patches[1].first_vertex, holed.num_vertices());
  EXPECT_EQ(topology_stats(m).boundary_loops, 2u) << "the rim and the second hole";
  remove_patches(m, patches, {0, 0});
  EXPECT_EQ(m.positions, holed.positions);
  EXPECT_EQ(m.faces, holed.faces);
}

TEST(FillHoles, OneThreadAndFourGiveTheSameMesh) {
  // Thirty holes of different sizes closed in parallel: the patches are
  // appended in loop order whatever thread made them.
  const Mesh grid = test::make_grid(60);
  const Mesh holed = without_faces(grid, [](const Vec3& c) {
    for (int k = 0; k < 30; ++k) {
      const Vec3 centre(6.0 + 9.0 * (k % 6), 6.0 + 11.0 * (k / 6), 0.0);
      if ((c - centre).norm() < 1.0 + 0.12 * k) return true;
    }
    return false;
  });
  const auto rings = hole_rings(holed, grid.positions);
  ASSERT_GE(rings.size(), 25u);
  Mesh one = holed, four = holed;
  {
    const ThreadScope threads(1);
    fill_holes(one, rings);
  }
  {
    const ThreadScope threads(4);
    fill_holes(four, rings);
  }
  ASSERT_GT(one.num_faces(), holed.num_faces());
  EXPECT_EQ(one.positions, four.positions);
  EXPECT_EQ(one.faces, four.faces);
  EXPECT_NEAR(total_area(one), 3600.0, 1e-6);
}

TEST(FillHoles, ALoopWhoseDiagonalsAreTakenGetsAFan) {
  // The square a b c d is open, but the mesh joins a-c and b-d elsewhere (two faces below it): every
  // triangulation of the loop would repeat one of those edges. It is closed by four faces around a new
  // vertex at its centre instead, manifold and oriented like the faces around it.
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},                 // a b c d
                 {0.5, -1, 0}, {2, 0.5, 0}, {0.5, 2, 0}, {-1, 0.5, 0},       // one face outside each side
                 {0.5, 0.5, -1}, {0.5, 0.5, -2}};                            // below: on a-c and on b-d
  m.faces = {{1, 0, 4}, {2, 1, 5}, {3, 2, 6}, {0, 3, 7}, {0, 2, 8}, {1, 3, 9}};
  Mesh filled = m;
  const std::vector<FilledHole> h = fill_holes(filled, {{0, 1, 2, 3}});
  ASSERT_EQ(h.size(), 1u);
  ASSERT_TRUE(h[0].filled);
  EXPECT_EQ(h[0].vertices, 1u);
  EXPECT_EQ(h[0].faces, 4u);
  EXPECT_LT((filled.positions[h[0].first_vertex] - Vec3(0.5, 0.5, 0)).norm(), 1e-12);
  const TopologyStats before = topology_stats(m), after = topology_stats(filled);
  EXPECT_EQ(after.nonmanifold_edges, 0u);
  EXPECT_EQ(after.inconsistent_edges, before.inconsistent_edges);
  for (std::size_t f = h[0].first_face; f < filled.num_faces(); ++f) {  // flat, facing +z like a b c d's neighbours
    const Face& t = filled.faces[f];
    const Vec3 n = (filled.positions[t[1]] - filled.positions[t[0]]).cross(filled.positions[t[2]] - filled.positions[t[0]]);
    EXPECT_GT(n.z(), 0.0);
  }
}

TEST(FillHoles, ASlitAtACopiedVertexIsZippedAndTheGridIsWholeAgain) {
  // The 4 x 4 grid cut along (1, 2) - (2, 2) - (3, 2): the faces above the cut use a copy of (2, 2), as
  // clean-up leaves a vertex it split. The loop (1,2) (2,2) (3,2) (2,2)' encloses no area.
  Mesh m = test::make_grid(4);
  const int v = 2 * 5 + 2, copy = static_cast<int>(m.num_vertices());
  m.positions.push_back(m.positions[v]);
  for (Face& f : m.faces)
    if ((m.positions[f[0]] + m.positions[f[1]] + m.positions[f[2]]).y() / 3.0 > 2.0)
      for (int& x : f)
        if (x == v) x = copy;
  std::vector<std::vector<int>> slit;
  for (auto& r : hole_rings(m, m.positions, true))
    if (std::find(r.begin(), r.end(), copy) != r.end()) slit.push_back(r);
  ASSERT_EQ(slit.size(), 1u);
  ASSERT_EQ(slit[0].size(), 4u);
  std::size_t zipped = 0;
  const auto left = zip_slits(m, slit, &zipped);
  EXPECT_TRUE(left.empty());
  EXPECT_EQ(zipped, 1u);
  // One of the two copies is left, and the grid is whole (clean-up would drop the other).
  bool uses_v = false, uses_copy = false;
  for (const Face& f : m.faces)
    for (int x : f) {
      uses_v |= x == v;
      uses_copy |= x == copy;
    }
  EXPECT_NE(uses_v, uses_copy);
  expect_whole_grid(m, 16.0);
  // A loop without coincident vertices is handed back as it came.
  Mesh hole = without_faces(test::make_grid(6), [](const Vec3& c) { return c.x() > 2 && c.x() < 4 && c.y() > 2 && c.y() < 4; });
  const auto rings = hole_rings(hole, hole.positions);
  ASSERT_EQ(rings.size(), 1u);
  const Mesh before = hole;
  EXPECT_EQ(zip_slits(hole, rings), rings);
  EXPECT_EQ(hole.faces, before.faces);
}
