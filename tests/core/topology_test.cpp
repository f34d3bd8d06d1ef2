#include "scanmesh/topology.h"

#include <gtest/gtest.h>

#include "helpers.h"
#include "scanmesh/errors.h"
#include "scanmesh/parallel.h"

using namespace scanmesh;

TEST(Topology, SquareOfTwoTriangles) {
  const Mesh m = test::make_grid(1);
  const Topology t = build_topology(m);
  EXPECT_EQ(t.edges.size(), 5u);
  EXPECT_EQ(t.num_boundary_edges(), 4u);
  EXPECT_EQ(t.num_nonmanifold_edges(), 0u);
  ASSERT_EQ(t.boundary_loops.size(), 1u);
  EXPECT_EQ(t.boundary_loops[0].size(), 4u);
  EXPECT_EQ(t.boundary_loop_closed[0], 1);
  for (int v = 0; v < 4; ++v) EXPECT_EQ(t.boundary_vertex[v], 1);
  ASSERT_EQ(t.face_faces.size(0), 1);
  EXPECT_EQ(*t.face_faces.begin(0), 1);
  // Vertex 0 and 3 are on the diagonal: both faces; 1 and 2 one face each.
  EXPECT_EQ(t.vertex_faces.size(0), 2);
  EXPECT_EQ(t.vertex_faces.size(1), 1);
  EXPECT_EQ(t.vertex_vertices.size(0), 3);
  EXPECT_EQ(t.vertex_vertices.size(1), 2);
}

TEST(Topology, BoundaryLoopFollowsFaceOrientation) {
  const Mesh m = test::make_grid(1);
  const Topology t = build_topology(m);
  const auto& loop = t.boundary_loops[0];
  // Each consecutive pair must be a directed edge of some face.
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const int a = loop[k], b = loop[(k + 1) % loop.size()];
    bool found = false;
    for (const Face& f : m.faces)
      for (int i = 0; i < 3; ++i) found = found || (f[i] == a && f[(i + 1) % 3] == b);
    EXPECT_TRUE(found) << a << "->" << b;
  }
}

TEST(Topology, ClosedTetrahedron) {
  const Mesh m = test::make_tetrahedron();
  const Topology t = build_topology(m);
  EXPECT_EQ(t.edges.size(), 6u);
  EXPECT_EQ(t.num_boundary_edges(), 0u);
  EXPECT_TRUE(t.boundary_loops.empty());
  for (int v = 0; v < 4; ++v) {
    EXPECT_EQ(t.vertex_vertices.size(v), 3);
    EXPECT_EQ(t.vertex_faces.size(v), 3);
    EXPECT_EQ(t.boundary_vertex[v], 0);
  }
  for (int f = 0; f < 4; ++f) EXPECT_EQ(t.face_faces.size(f), 3);
  EXPECT_EQ(count_components(m, t), 1u);
}

TEST(Topology, NonManifoldEdgeDegenerateFaceIsolatedVertexComponents) {
  Mesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1),
                 Vec3(5, 5, 5),  // isolated
                 Vec3(9, 0, 0), Vec3(10, 0, 0), Vec3(9, 1, 0)};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4},  // three faces on edge 0-1
             {6, 7, 8}, {6, 6, 7}};            // second component with a degenerate face
  const Topology t = build_topology(m);
  EXPECT_EQ(t.num_nonmanifold_edges(), 1u);
  EXPECT_EQ(t.vertex_faces.size(5), 0);
  EXPECT_EQ(t.vertex_vertices.size(5), 0);
  EXPECT_EQ(count_components(m, t), 2u);
  EXPECT_EQ(t.vertex_faces.size(6), 2);  // the degenerate face lists vertex 6 once
}

TEST(Topology, GridCounts) {
  const Mesh m = test::make_grid(4);
  const Topology t = build_topology(m);
  // V - E + F = 1 for a disc.
  EXPECT_EQ(static_cast<long>(m.num_vertices()) - static_cast<long>(t.edges.size()) + static_cast<long>(m.num_faces()), 1);
  EXPECT_EQ(t.num_boundary_edges(), 16u);
  ASSERT_EQ(t.boundary_loops.size(), 1u);
  EXPECT_EQ(t.boundary_loops[0].size(), 16u);
}

TEST(Topology, WithoutFaceFacesEverythingElseIsTheSame) {
  // An open grid and a closed sphere: the lighter build differs only in face_faces.
  for (const Mesh& m : {test::make_grid(5), test::make_sphere(2)}) {
    const Topology full = build_topology(m), light = build_topology(m, false);
    EXPECT_GT(full.face_faces.indices.size(), 0u);
    EXPECT_TRUE(light.face_faces.indices.empty());
    EXPECT_EQ(light.vertex_faces.offsets, full.vertex_faces.offsets);
    EXPECT_EQ(light.vertex_faces.indices, full.vertex_faces.indices);
    EXPECT_EQ(light.vertex_vertices.indices, full.vertex_vertices.indices);
    EXPECT_EQ(light.edges, full.edges);
    EXPECT_EQ(light.edge_faces.indices, full.edge_faces.indices);
    EXPECT_EQ(light.face_edges, full.face_edges);
    EXPECT_EQ(light.boundary_vertex, full.boundary_vertex);
    EXPECT_EQ(light.boundary_loops, full.boundary_loops);
  }
}

TEST(Mesh, ValidateNamesTheProblem) {
  Mesh m = test::make_grid(1);
  m.faces[1][2] = 7;
  try {
    validate_mesh(m, "thing.obj");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("thing.obj"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("vertex 7"), std::string::npos);
  }
  m = test::make_grid(1);
  m.positions[2].y() = std::nan("");
  EXPECT_THROW(validate_mesh(m, "x"), InputError);
}

TEST(Parallel, AThreadScopeSetsTheCountAndRestoresIt) {
  scanmesh::set_thread_count(2);
  {
    const scanmesh::ThreadScope one(1);
    EXPECT_EQ(scanmesh::thread_count(), 1);
  }
  EXPECT_EQ(scanmesh::thread_count(), 2);
  scanmesh::set_thread_count(0);
}
