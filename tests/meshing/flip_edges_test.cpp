// flip_edges: rounder triangles over the same points, without folding or cutting a sharp edge.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "helpers.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/flip_edges.h"
#include "scanmesh/geometry.h"

using namespace scanmesh;

namespace {

double angle_at(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 u = a - p, v = b - p;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

// The largest sum of the two angles opposite an interior edge (pi or less: Delaunay).
double worst_opposite_sum(const Mesh& m) {
  std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> sides;  // edge -> (face, opposite corner)
  for (std::size_t f = 0; f < m.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = m.faces[f][k], b = m.faces[f][(k + 1) % 3], c = m.faces[f][(k + 2) % 3];
      sides[{std::min(a, b), std::max(a, b)}].emplace_back(static_cast<int>(f), c);
    }
  double worst = 0.0;
  for (const auto& [e, s] : sides)
    if (s.size() == 2)
      worst = std::max(worst, angle_at(m.positions[s[0].second], m.positions[e.first], m.positions[e.second]) +
                                  angle_at(m.positions[s[1].second], m.positions[e.first], m.positions[e.second]));
  return worst;
}

// A flat grid whose points are jittered within the plane and whose quads are all cut along the same
// diagonal: many edges are not Delaunay.
Mesh jittered_grid(int n, unsigned seed) {
  Mesh m = test::make_grid(n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (auto& p : m.positions) p += Vec3(u(rng), u(rng), 0.0);
  return m;
}

}  // namespace

// A plane stays the plane it was, with the same points, and becomes Delaunay; no face turns over.
TEST(FlipEdges, AJitteredPlaneBecomesDelaunayOverTheSamePoints) {
  Mesh m = jittered_grid(12, 7);
  const Mesh before = m;
  ASSERT_GT(worst_opposite_sum(m), M_PI + 0.1);
  const FlipReport r = flip_edges(m);
  EXPECT_GT(r.flips, 0u);
  EXPECT_EQ(m.positions, before.positions);
  EXPECT_EQ(m.faces.size(), before.faces.size());
  EXPECT_LE(worst_opposite_sum(m), M_PI + 1e-6);
  for (const Face& f : m.faces) EXPECT_GT(triangle_normal(m.positions[f[0]], m.positions[f[1]], m.positions[f[2]]).z(), 0.0);
  // Rounder: the worst triangle is better than before.
  double worst_before = 0.0, worst_after = 0.0;
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    const Face &a = before.faces[f], &b = m.faces[f];
    worst_before = std::max(worst_before, triangle_shape(before.positions[a[0]], before.positions[a[1]], before.positions[a[2]]));
    worst_after = std::max(worst_after, triangle_shape(m.positions[b[0]], m.positions[b[1]], m.positions[b[2]]));
  }
  EXPECT_LT(worst_after, worst_before);
}

// A Delaunay mesh is a fixed point: the regular cube (right triangles, opposite angles summing to pi).
TEST(FlipEdges, ADelaunayMeshIsAFixedPoint) {
  Mesh m = test::make_cube(6);
  const Mesh before = m;
  EXPECT_EQ(flip_edges(m).flips, 0u);
  EXPECT_EQ(m.faces, before.faces);
}

// A noisy plane, as a scan's points triangulated: the same points, no face turned over, rounder
// triangles and no sharper bends than before.
TEST(FlipEdges, ANoisyPlaneGetsRounderTrianglesWithoutFolds) {
  Mesh m = jittered_grid(30, 11);
  std::mt19937 rng(5);
  std::normal_distribution<double> z(0.0, 0.05);
  for (auto& p : m.positions) p.z() = z(rng);
  const Mesh before = m;
  const FlipReport r = flip_edges(m);
  EXPECT_GT(r.flips, 0u);
  EXPECT_EQ(m.positions, before.positions);
  double q_before = 0.0, q_after = 0.0;
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    const Face &a = before.faces[f], &b = m.faces[f];
    EXPECT_GT(triangle_normal(m.positions[b[0]], m.positions[b[1]], m.positions[b[2]]).z(), 0.0) << "face " << f;
    q_before += triangle_shape(before.positions[a[0]], before.positions[a[1]], before.positions[a[2]]);
    q_after += triangle_shape(m.positions[b[0]], m.positions[b[1]], m.positions[b[2]]);
  }
  EXPECT_LT(q_after, q_before);
}

// A pair of slivers along an edge is flipped to the rounder pair across it, and then bends less.
TEST(FlipEdges, APairOfSliversIsFlippedAcrossAndBendsLess) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 0.1, 0.02}, {0.5, -0.1, 0.02}, {-0.5, 0.5, 0}, {1.5, 0.5, 0}, {-0.5, -0.5, 0}, {1.5, -0.5, 0}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 2, 4}, {2, 1, 5}, {3, 0, 6}, {1, 3, 7}};
  auto bend = [&m](int f, int g) {
    const Face &p = m.faces[f], &q = m.faces[g];
    return std::acos(triangle_normal(m.positions[p[0]], m.positions[p[1]], m.positions[p[2]])
                         .dot(triangle_normal(m.positions[q[0]], m.positions[q[1]], m.positions[q[2]])));
  };
  ASSERT_GT(angle_at(m.positions[2], m.positions[0], m.positions[1]) + angle_at(m.positions[3], m.positions[0], m.positions[1]), M_PI);
  const double before = bend(0, 1);
  EXPECT_EQ(flip_edges(m).flips, 1u);
  EXPECT_EQ(m.faces[0], (Face{0, 3, 2}));
  EXPECT_EQ(m.faces[1], (Face{3, 1, 2}));
  EXPECT_LT(bend(0, 1), before);
}

// A flip that calls for it by its angles but would bend the pair more than it was, and more than the
// limit, is not made (a quad found by sampling random ones: 34 degrees between the old faces, 45 between
// the new ones); with a looser limit it is.
TEST(FlipEdges, AFlipThatWouldBendThePairMoreIsNotMade) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0.1, 0}, {0.3, -0.3, 0.2}, {-0.5, 0.5, 0}, {1.5, 0.5, 0}, {-0.5, -0.5, 0}, {1.5, -0.5, 0}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 2, 4}, {2, 1, 5}, {3, 0, 6}, {1, 3, 7}};
  ASSERT_GT(angle_at(m.positions[2], m.positions[0], m.positions[1]) + angle_at(m.positions[3], m.positions[0], m.positions[1]), M_PI);
  const Mesh before = m;
  flip_edges(m, 30.0);
  EXPECT_EQ(m.faces[0], before.faces[0]);
  EXPECT_EQ(m.faces[1], before.faces[1]);
  Mesh loose = before;
  flip_edges(loose, 90.0);
  EXPECT_EQ(loose.faces[0], (Face{0, 3, 2}));
  EXPECT_EQ(loose.faces[1], (Face{3, 1, 2}));
}

// Running it again changes nothing, and the same input gives the same faces.
TEST(FlipEdges, TheResultIsDeterministicAndAFixedPoint) {
  Mesh a = jittered_grid(20, 3), b = jittered_grid(20, 3);
  flip_edges(a);
  flip_edges(b);
  EXPECT_EQ(a.faces, b.faces);
  const Mesh once = a;
  flip_edges(a);
  EXPECT_EQ(a.faces, once.faces);
}

// Edges with three faces and faces that disagree about the orientation are left alone (no crash, no change).
TEST(FlipEdges, NonManifoldAndMisorientedEdgesAreLeftAlone) {
  Mesh m = jittered_grid(4, 5);
  for (auto& f : m.faces) std::swap(f[1], f[2]);  // all reversed: still consistent
  Mesh mixed = m;
  std::swap(mixed.faces[0][1], mixed.faces[0][2]);  // one face against its neighbours
  mixed.faces.push_back({mixed.faces[1][0], mixed.faces[1][1], static_cast<int>(mixed.positions.size())});
  mixed.positions.push_back({0.0, 0.0, 1.0});  // a third face on an edge
  const Mesh before = mixed;
  flip_edges(mixed);
  EXPECT_EQ(mixed.positions, before.positions);
  EXPECT_EQ(mixed.faces[0], before.faces[0]);
  EXPECT_EQ(mixed.faces.back(), before.faces.back());
  Mesh empty;
  EXPECT_EQ(flip_edges(empty).flips, 0u);
}

// The test both flip_edges and hole filling's patches use, on single quads: edge (a, b) between the
// triangles (a, b, c) and (b, a, d).
TEST(FlipEdges, TheSharedFlipTestOnSingleQuads) {
  const Vec3 a(0, 0, 0), b(4, 0, 0);
  // A flat kite whose apexes lie close to the edge: their angles sum past pi, the other diagonal is better.
  EXPECT_TRUE(should_flip(a, b, Vec3(2, 0.5, 0), Vec3(2, -0.5, 0), -1.0));
  // Apexes far from the edge: their angles sum below pi, the edge is Delaunay already.
  EXPECT_FALSE(should_flip(a, b, Vec3(2, 3, 0), Vec3(2, -3, 0), -1.0));
  // A degenerate old triangle (c on the edge) is never flipped.
  EXPECT_FALSE(should_flip(a, b, Vec3(2, 0, 0), Vec3(2, -0.5, 0), -1.0));
  // The sampled quad of the test above: the new pair bends more than the old (34 -> 45 degrees); allowed
  // with no limit or a limit above that, refused below it.
  const Vec3 p(0, 0, 0), q(1, 0, 0), c(0, 0.1, 0), d(0.3, -0.3, 0.2);
  const auto bend = [](const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s, const Vec3& t, const Vec3& u) {
    const Vec3 n = (q - p).cross(r - p).normalized(), m = (t - s).cross(u - s).normalized();
    return std::acos(std::clamp(n.dot(m), -1.0, 1.0)) * 180.0 / M_PI;
  };
  const double before = bend(p, q, c, q, p, d), after = bend(p, d, c, d, q, c);
  ASSERT_GT(after, before);
  EXPECT_TRUE(should_flip(p, q, c, d, -1.0));
  EXPECT_FALSE(should_flip(p, q, c, d, std::cos(0.5 * (before + after) * M_PI / 180.0)));
  EXPECT_TRUE(should_flip(p, q, c, d, std::cos((after + 1.0) * M_PI / 180.0)));  // within the limit
}
