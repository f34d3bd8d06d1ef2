#include "scanmesh/boundary_curves.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "helpers.h"

using namespace scanmesh;

namespace {

int count(const std::vector<std::uint8_t>& flags, const Topology& t) {
  int n = 0;
  for (std::size_t v = 0; v < flags.size(); ++v) n += t.boundary_vertex[v] && flags[v] ? 1 : 0;
  return n;
}

}  // namespace

TEST(BoundaryCurves, FindsTheCornersOfASquare) {
  for (int n : {3, 8, 20}) {
    const Mesh grid = test::make_grid(n);
    const Topology t = build_topology(grid);
    const BoundaryCurves c = build_boundary_curves(grid, t);
    EXPECT_EQ(count(c.corner, t), 4) << n << " x " << n;
    EXPECT_EQ(count(c.ragged, t), 0);
    for (int corner : {0, n, n * (n + 1), (n + 1) * (n + 1) - 1}) EXPECT_TRUE(c.corner[corner]) << corner;
  }
}

TEST(BoundaryCurves, SmallLoopsArePolygons) {
  // A triangle's or a quad's boundary is all corners and never "ragged" (which would smooth it inwards).
  Mesh triangle;
  triangle.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  triangle.faces = {{0, 1, 2}};
  for (const Mesh& m : {triangle, test::make_grid(1)}) {
    const Topology t = build_topology(m);
    const BoundaryCurves c = build_boundary_curves(m, t);
    EXPECT_EQ(count(c.corner, t), static_cast<int>(m.num_vertices()));
    EXPECT_EQ(count(c.ragged, t), 0);
  }
}

TEST(BoundaryCurves, APixelStaircaseIsRagged) {
  // A depth image meshed pixel by pixel, each triangle kept where its pixel's depth is valid (inside a
  // disc, on alternating diagonals): the rim zigzags between axis steps and diagonals.
  Mesh m;
  const int w = 30;
  for (int j = 0; j <= w; ++j)
    for (int i = 0; i <= w; ++i) m.positions.emplace_back(i, j, 0.0);
  auto inside = [&](double x, double y) { return std::hypot(x - w / 2.0, y - w / 2.0) < w / 2.5; };
  for (int j = 0; j < w; ++j)
    for (int i = 0; i < w; ++i) {
      const int a = j * (w + 1) + i;
      const bool flip = (i + j) % 2 != 0;
      const Face t1 = flip ? Face{a, a + 1, a + w + 1} : Face{a, a + 1, a + w + 2};
      const Face t2 = flip ? Face{a + 1, a + w + 2, a + w + 1} : Face{a, a + w + 2, a + w + 1};
      for (const Face& f : {t1, t2}) {
        const Vec3 c = (m.positions[f[0]] + m.positions[f[1]] + m.positions[f[2]]) / 3.0;
        if (inside(c.x(), c.y())) m.faces.push_back(f);
      }
    }
  const Topology t = build_topology(m);
  const BoundaryCurves c = build_boundary_curves(m, t);
  EXPECT_GT(count(c.ragged, t), 0);
}

TEST(BoundaryCurves, ANoisyCircleStaysACircleOfTheSameRadius) {
  // A disc whose rim is jittered along the rim's normal: the curve fit removes the jitter without
  // shrinking the rim (a mean-curvature flow would).
  Mesh m = test::make_cap(12, 64, 1.2);
  const Topology t = build_topology(m);
  std::mt19937 rng(3);
  std::normal_distribution<double> jitter(0.0, 0.01);
  const std::vector<int> rim = test::boundary_vertices(t);
  const double radius = std::hypot(m.positions[rim[0]].x(), m.positions[rim[0]].y());
  for (int v : rim) {
    Vec3& p = m.positions[v];
    const double r = std::hypot(p.x(), p.y());
    p.x() *= (r + jitter(rng)) / r;
    p.y() *= (r + jitter(rng)) / r;
  }
  const BoundaryCurves c = build_boundary_curves(m, t);
  for (int pass = 0; pass < 20; ++pass) smooth_boundary_curves(m.positions, m.faces, t, c, 2.0);
  double mean = 0.0, spread = 0.0;
  for (int v : rim) mean += std::hypot(m.positions[v].x(), m.positions[v].y());
  mean /= static_cast<double>(rim.size());
  for (int v : rim) spread = std::max(spread, std::abs(std::hypot(m.positions[v].x(), m.positions[v].y()) - mean));
  EXPECT_NEAR(mean, radius, 0.002);  // no shrinkage
  EXPECT_LT(spread, 0.01);           // the jitter is gone (it was up to ~0.03)
}

TEST(BoundaryCurves, VerticesMoveAcrossTheCurveNotAlongIt) {
  // The fit's target along the curve is set by each vertex's own noisy arc length, so a move along the
  // curve is a random step; over many iterations those steps walk the boundary vertices away from where
  // they were measured. A rim jittered in every direction: each move must be across the chord of the
  // vertex's two curve neighbours.
  Mesh m = test::make_cap(12, 64, 1.2);
  const Topology t = build_topology(m);
  std::mt19937 rng(5);
  std::normal_distribution<double> jitter(0.0, 0.01);
  for (std::size_t v = 0; v < m.num_vertices(); ++v)
    if (t.boundary_vertex[v]) m.positions[v] += Vec3(jitter(rng), jitter(rng), jitter(rng));
  const BoundaryCurves c = build_boundary_curves(m, t);
  const std::vector<Vec3> before = m.positions;
  smooth_boundary_curves(m.positions, m.faces, t, c, 2.0);
  int moved = 0;
  for (std::size_t v = 0; v < m.num_vertices(); ++v) {
    if (!t.boundary_vertex[v] || c.prev[v] < 0 || c.next[v] < 0) continue;
    const Vec3 move = m.positions[v] - before[v];
    if (move.norm() < 1e-9) continue;
    ++moved;
    const Vec3 chord = (before[c.next[v]] - before[c.prev[v]]).normalized();
    EXPECT_NEAR(move.dot(chord), 0.0, 1e-12 + 1e-9 * move.norm()) << "vertex " << v;
  }
  EXPECT_GT(moved, 32);  // the fit did move most of the 64 rim vertices

  // Under impulsive noise the vertices that move are off along the curve by their impulse: they take the
  // whole move, along the curve too.
  std::vector<Vec3> free = before;
  smooth_boundary_curves(free, m.faces, t, c, 2.0, true);
  double along = 0.0;
  for (std::size_t v = 0; v < m.num_vertices(); ++v)
    if (t.boundary_vertex[v] && c.prev[v] >= 0 && c.next[v] >= 0)
      along = std::max(along, std::abs((free[v] - before[v]).dot((before[c.next[v]] - before[c.prev[v]]).normalized())));
  EXPECT_GT(along, 1e-3);  // the jitter along the rim is 0.01
}

TEST(BoundaryCurves, ImpulsesAlongTheRimAreFoundAndTheSquaresCornersAreNot) {
  // A smooth rim (a disc's circle, with slight jitter so the median jump is not zero) with three
  // vertices pushed off it: those three are the outliers, and nothing else is.
  Mesh m = test::make_cap(12, 64, 1.2);
  const Topology t = build_topology(m);
  const std::vector<int> rim = test::boundary_vertices(t);
  test::jitter_3d(m, rim, 0.002, 5);
  const BoundaryCurves c = build_boundary_curves(m, t);
  std::vector<int> pushed;
  for (int v = rim[5]; pushed.size() < 3; v = c.next[c.next[c.next[c.next[c.next[v]]]]]) {
    m.positions[v] += Vec3(0.0, 0.0, 0.05);  // ~ half a rim edge (2 pi 0.93 / 64)
    pushed.push_back(v);
  }
  const std::vector<std::uint8_t> out = boundary_outliers(m.positions, c, 4.0);
  for (std::size_t v = 0; v < out.size(); ++v)
    EXPECT_EQ(out[v] != 0, std::find(pushed.begin(), pushed.end(), static_cast<int>(v)) != pushed.end()) << v;

  // A clean square's rim: its corners are corners, not impulses; its straight sides have no jumps.
  const Mesh grid = test::make_grid(8);
  const Topology tg = build_topology(grid);
  EXPECT_EQ(count(boundary_outliers(grid.positions, build_boundary_curves(grid, tg), 4.0), tg), 0);
}
