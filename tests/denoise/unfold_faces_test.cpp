#include "scanmesh/unfold_faces.h"

#include <gtest/gtest.h>

#include <cmath>

#include "helpers.h"

using namespace scanmesh;

namespace {

std::vector<Vec3> up(const Mesh& m) { return std::vector<Vec3>(m.faces.size(), Vec3(0, 0, 1)); }

int turned(const Mesh& m, const std::vector<Vec3>& positions) {
  int n = 0;
  for (const Face& f : m.faces) n += (positions[f[1]] - positions[f[0]]).cross(positions[f[2]] - positions[f[0]]).z() < 0.0 ? 1 : 0;
  return n;
}

// The grid's positions with vertex v moved by `by`.
std::vector<Vec3> pulled(const Mesh& grid, int v, const Vec3& by) {
  std::vector<Vec3> p = grid.positions;
  p[static_cast<std::size_t>(v)] += by;
  return p;
}

}  // namespace

TEST(UnfoldFaces, AFoldInAPlaneIsUndoneWithinThePlane) {
  const Mesh grid = test::make_grid(8);
  const Topology t = build_topology(grid);
  const int v = 4 * 9 + 4;  // an interior vertex, pulled across its neighbours' edges
  const std::vector<Vec3> folded = pulled(grid, v, Vec3(1.6, 0.3, 0.0));
  ASSERT_GT(turned(grid, folded), 0);
  std::vector<Vec3> p = folded;
  const UnfoldReport r = unfold_faces(p, grid.faces, t, grid.positions, up(grid));
  EXPECT_GT(r.folds, 0u);
  EXPECT_EQ(r.remaining, 0u);
  EXPECT_EQ(turned(grid, p), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(p[i].z(), 0.0) << i;  // moves stay in the plane
    // Only the fold's corners move.
    if ((grid.positions[i] - grid.positions[v]).norm() > 1.5) {
      EXPECT_EQ(p[i], folded[i]) << i;
    }
  }
}

TEST(UnfoldFaces, AMeshWithoutFoldsIsAFixedPoint) {
  const Mesh sphere = test::make_sphere(3);
  const Topology t = build_topology(sphere);
  FaceGeometry g;
  compute_face_geometry(sphere.positions, sphere.faces, g);
  std::vector<Vec3> p = sphere.positions;
  const UnfoldReport r = unfold_faces(p, sphere.faces, t, sphere.positions, g.normals);
  EXPECT_EQ(r.folds, 0u);
  EXPECT_EQ(r.moved, 0u);
  EXPECT_EQ(p, sphere.positions);
}

TEST(UnfoldFaces, ABoundaryVertexMovesAlongTheBoundary) {
  const Mesh grid = test::make_grid(6);
  const Topology t = build_topology(grid);
  const int v = 3;  // on the edge y = 0, pulled along it past its neighbour
  std::vector<Vec3> p = pulled(grid, v, Vec3(1.5, 0.0, 0.0));
  ASSERT_GT(turned(grid, p), 0);
  const UnfoldReport r = unfold_faces(p, grid.faces, t, grid.positions, up(grid));
  EXPECT_EQ(r.remaining, 0u);
  EXPECT_EQ(turned(grid, p), 0);
  EXPECT_EQ(p[v].y(), 0.0);  // still on the boundary line
  EXPECT_EQ(p[v].z(), 0.0);
}

TEST(UnfoldFaces, FacesTurnedWithTheirWholeNeighbourhoodAreLeftAlone) {
  // A reference that disagrees with every face is what is off (as across a thin wall): nothing is a fold.
  const Mesh grid = test::make_grid(5);
  const Topology t = build_topology(grid);
  std::vector<Vec3> p = grid.positions;
  const UnfoldReport r = unfold_faces(p, grid.faces, t, grid.positions, std::vector<Vec3>(grid.faces.size(), Vec3(0, 0, -1)));
  EXPECT_EQ(r.folds, 0u);
  EXPECT_EQ(p, grid.positions);
}

TEST(UnfoldFaces, SliversOfTheInputAreLeftAlone) {
  // A fold whose faces were slivers before denoising: their normals are noise, so they are not moved.
  Mesh grid = test::make_grid(8);
  const int v = 4 * 9 + 4;
  std::vector<Vec3> input = grid.positions;
  input[v] = grid.positions[v + 1] + Vec3(-0.01, 0.0, 0.0);  // squashed against its neighbour: slivers
  std::vector<Vec3> p = input;
  p[v] += Vec3(0.05, 0.0, 0.0);  // across the neighbour: turned
  ASSERT_GT(turned(grid, p), 0);
  const std::vector<Vec3> before = p;
  const Topology t = build_topology(grid);
  const UnfoldReport r = unfold_faces(p, grid.faces, t, input, up(grid));
  EXPECT_EQ(r.moved, 0u);
  EXPECT_EQ(p, before);

  // On a triangulation of scanned points the slivers are the triangulation's, and the same fold is undone.
  const UnfoldReport scanned = unfold_faces(p, grid.faces, t, input, up(grid), 10, 0.5, true);
  EXPECT_GT(scanned.folds, 0u);
  EXPECT_EQ(scanned.remaining, 0u);
  EXPECT_EQ(turned(grid, p), 0);
  for (const Vec3& q : p) EXPECT_EQ(q.z(), 0.0);  // within the plane
}

TEST(UnfoldFaces, OnlyMovesThatUndoAFoldOrStraightenItAreMade) {
  // A roof (two planes meeting at the ridge x = 4), the reference its clean normals. A vertex pulled
  // within its plane past its neighbour folds two faces; of the folds' corners, moving the pulled vertex
  // and one neighbour undoes them. The other corners' moves would turn no fewer faces and lean them no
  // less from the reference: they are not made (they were, and drifted, before).
  Mesh roof = test::make_grid(8);
  for (auto& p : roof.positions) p.z() = 0.5 * (4.0 - std::abs(p.x() - 4.0));
  const Topology t = build_topology(roof);
  FaceGeometry g;
  compute_face_geometry(roof.positions, roof.faces, g);
  const int v = 4 * 9 + 3;  // x = 3, y = 4
  std::vector<Vec3> p = roof.positions;
  p[v] += Vec3(-1.3, 0.0, -0.65);
  const UnfoldReport r = unfold_faces(p, roof.faces, t, roof.positions, g.normals);
  EXPECT_GT(r.folds, 0u);
  EXPECT_EQ(r.remaining, 0u);
  for (std::size_t f = 0; f < roof.faces.size(); ++f) {
    const Face& a = roof.faces[f];
    EXPECT_GT((p[a[1]] - p[a[0]]).cross(p[a[2]] - p[a[0]]).dot(g.normals[f]), 0.0) << f;
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (roof.positions[i].y() != 4.0) {
      EXPECT_EQ(p[i], roof.positions[i]) << i;
    }
  }
}

TEST(UnfoldFaces, AFoldOfTheInputGetsTheReferenceOfTheSurfaceAroundIt) {
  // The noise pulled a vertex across its neighbours' edges. The robust prefilter leaves the folded
  // faces' normals as they are (a neighbour 180 degrees away weighs nothing), so their reference points
  // down with them; fold_reference turns it back to the plane's, and the fold can then be undone.
  const Mesh grid = test::make_grid(8);
  const Topology t = build_topology(grid);
  const int v = 4 * 9 + 4;
  const std::vector<Vec3> folded = pulled(grid, v, Vec3(1.6, 0.3, 0.0));
  FaceGeometry g;
  compute_face_geometry(folded, grid.faces, g);
  ASSERT_GT(turned(grid, folded), 0);
  const std::vector<Vec3> reference = fold_reference(g.normals, grid.faces, t, g.areas);
  for (std::size_t f = 0; f < grid.faces.size(); ++f) {
    EXPECT_EQ(reference[f], Vec3(0, 0, 1)) << f;
  }
  std::vector<Vec3> p = folded;
  unfold_faces(p, grid.faces, t, folded, reference);
  EXPECT_EQ(turned(grid, p), 0);
  // With the faces' own normals as the reference nothing looks folded.
  std::vector<Vec3> q = folded;
  EXPECT_EQ(unfold_faces(q, grid.faces, t, folded, g.normals).folds, 0u);
}

TEST(UnfoldFaces, ASurfaceWithoutFoldsKeepsItsReference) {
  // Every face of a closed sphere and of a roof agrees with the faces around its corners.
  for (const Mesh& m : {test::make_sphere(3), test::make_grid(6)}) {
    Mesh shape = m;
    if (shape.positions.size() == 49) {  // the grid, folded into a roof along x = 3
      for (auto& p : shape.positions) p.z() = 0.8 * (3.0 - std::abs(p.x() - 3.0));
    }
    FaceGeometry g;
    compute_face_geometry(shape.positions, shape.faces, g);
    EXPECT_EQ(fold_reference(g.normals, shape.faces, build_topology(shape), g.areas), g.normals);
  }
}
