#include "scanmesh/topology.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <set>

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

namespace {

// Topology written the plain way (maps and sets), to check the counted, in-place build against.
struct Reference {
  std::vector<std::vector<int>> vertex_faces, vertex_vertices, edge_faces, face_faces;
  std::vector<std::array<int, 2>> edges;
  std::vector<std::array<int, 3>> face_edges;
};

Reference reference_topology(const Mesh& m) {
  Reference r;
  const std::size_t nv = m.num_vertices(), nf = m.num_faces();
  std::vector<std::set<int>> vf(nv), vv(nv), ff(nf);
  std::map<std::array<int, 2>, std::vector<std::pair<int, int>>> half;  // edge -> (face, corner), ascending
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int u = m.faces[f][k], w = m.faces[f][(k + 1) % 3];
      vf[u].insert(static_cast<int>(f));
      half[{std::min(u, w), std::max(u, w)}].emplace_back(static_cast<int>(f), k);
    }
  r.face_edges.assign(nf, {-1, -1, -1});
  for (auto& [e, list] : half) {
    std::sort(list.begin(), list.end());
    const int index = static_cast<int>(r.edges.size());
    r.edges.push_back(e);
    std::vector<int> faces;
    for (const auto& [f, k] : list) {
      r.face_edges[f][k] = index;
      if (faces.empty() || faces.back() != f) faces.push_back(f);
    }
    for (std::size_t i = 0; i + 1 < faces.size(); ++i) ff[faces[i]].insert(faces[i + 1]), ff[faces[i + 1]].insert(faces[i]);
    r.edge_faces.push_back(faces);
    if (e[0] != e[1]) vv[e[0]].insert(e[1]), vv[e[1]].insert(e[0]);
  }
  for (const auto& s : vf) r.vertex_faces.emplace_back(s.begin(), s.end());
  for (const auto& s : vv) r.vertex_vertices.emplace_back(s.begin(), s.end());
  for (const auto& s : ff) r.face_faces.emplace_back(s.begin(), s.end());
  return r;
}

std::vector<std::vector<int>> rows_of(const Adjacency& a) {
  std::vector<std::vector<int>> rows;
  for (std::size_t i = 0; i < a.rows(); ++i) rows.emplace_back(a.begin(i), a.end(i));
  return rows;
}

}  // namespace

TEST(Topology, EqualsAPlainBuildOnAHostileSoupForAnyThreadCount) {
  // A sphere plus a soup of random faces over few vertices: degenerate faces (a vertex named twice or
  // three times), repeated faces, edges with many faces, isolated vertices.
  Mesh m = test::make_sphere(3);
  std::mt19937 rng(7);
  const int base = static_cast<int>(m.num_vertices());
  for (int i = 0; i < 40; ++i) m.positions.push_back(Vec3(i, 0.5 * i, 0.0));
  std::uniform_int_distribution<int> pick(0, 29);  // vertices base+30..base+39 stay isolated
  for (int i = 0; i < 600; ++i) m.faces.push_back({base + pick(rng), base + pick(rng), base + pick(rng)});
  m.faces.push_back({3, 3, 3});
  m.faces.push_back(m.faces[5]);
  const Reference r = reference_topology(m);
  for (int threads : {1, 3}) {
    const ThreadScope scope(threads);
    const Topology t = build_topology(m);
    EXPECT_EQ(rows_of(t.vertex_faces), r.vertex_faces);
    EXPECT_EQ(rows_of(t.vertex_vertices), r.vertex_vertices);
    EXPECT_EQ(t.edges, r.edges);
    EXPECT_EQ(rows_of(t.edge_faces), r.edge_faces);
    EXPECT_EQ(t.face_edges, r.face_edges);
    EXPECT_EQ(rows_of(t.face_faces), r.face_faces);
    // A caller that released the two neighbour tables (or built without face_faces) rebuilds them the same.
    Topology light = build_topology(m, false);
    ASSERT_EQ(light.face_faces.rows(), 0u);
    std::vector<int>().swap(light.vertex_vertices.indices);
    light.vertex_vertices.offsets.assign(1, 0);
    add_vertex_vertices(light);
    std::vector<std::array<int, 3>>().swap(light.face_edges);  // not needed for it
    add_face_faces(light, m.num_faces());
    EXPECT_EQ(rows_of(light.vertex_vertices), r.vertex_vertices);
    EXPECT_EQ(rows_of(light.face_faces), r.face_faces);
    EXPECT_EQ(light.face_faces.offsets, t.face_faces.offsets);
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

TEST(Parallel, AnOrderedSumHasTheSameBitsForEveryThreadCount) {
  // Terms whose sum depends on the order of the additions (1e16 + 1 - 1e16 is 0 or 1): any thread count
  // must add them as blocks of 1024 in order, block sums in order.
  const long n = 10000;
  auto term = [](long i) { return i % 3 == 0 ? 1e16 : (i % 3 == 1 ? 1.0 + 1e-3 * static_cast<double>(i) : -1e16); };
  double serial = 0.0;
  for (long b = 0; b < n; b += 1024) {
    double s = 0.0;
    for (long i = b; i < std::min(n, b + 1024); ++i) s += term(i);
    serial += s;
  }
  for (int threads : {1, 2, 3, 7}) {
    const scanmesh::ThreadScope scope(threads);
    EXPECT_EQ(scanmesh::ordered_sum(n, 0.0, term), serial) << threads << " threads";
  }
  EXPECT_EQ(scanmesh::ordered_sum(0, 0.0, term), 0.0);
}

TEST(Topology, VertexPiecesAreLabelledByTheirSmallestVertex) {
  // Faces 0-1-2 and 2-3-4 meet at vertex 2 (one piece through a shared vertex only), 5-6-7 stands alone,
  // vertex 8 is used by no face; the labels agree with count_components.
  Mesh m;
  m.positions.assign(9, Vec3::Zero());
  m.faces = {{4, 3, 2}, {7, 6, 5}, {2, 1, 0}};
  const std::vector<int> piece = vertex_pieces(m);
  EXPECT_EQ(piece, (std::vector<int>{0, 0, 0, 0, 0, 5, 5, 5, 8}));
  EXPECT_EQ(count_components(m, build_topology(m)), 2u);
}
