#include "scanmesh/closest_point.h"

#include <gtest/gtest.h>

#include <random>

#include "helpers.h"

using namespace scanmesh;

namespace {

double brute_force(const Mesh& m, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Face& f : m.faces)
    best = std::min(best, (closest_point_on_triangle(p, m.positions[f[0]], m.positions[f[1]], m.positions[f[2]]) - p).norm());
  return best;
}

}  // namespace

TEST(ClosestPoint, TriangleRegions) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_LT((closest_point_on_triangle(Vec3(0.2, 0.2, 5), a, b, c) - Vec3(0.2, 0.2, 0)).norm(), 1e-15);  // face
  EXPECT_EQ(closest_point_on_triangle(Vec3(-1, -1, 1), a, b, c), a);                    // vertex
  EXPECT_EQ(closest_point_on_triangle(Vec3(0.5, -2, 0), a, b, c), Vec3(0.5, 0, 0));     // edge
  const Vec3 q = closest_point_on_triangle(Vec3(1, 1, 0), a, b, c);                      // hypotenuse
  EXPECT_NEAR(q.x(), 0.5, 1e-15);
  EXPECT_NEAR(q.y(), 0.5, 1e-15);
  // Degenerate (collinear) triangle: distance to the segment.
  const Vec3 d = closest_point_on_triangle(Vec3(0.5, 1, 0), a, b, Vec3(2, 0, 0));
  EXPECT_NEAR((d - Vec3(0.5, 0, 0)).norm(), 0.0, 1e-15);
}

TEST(ClosestPoint, IndexMatchesBruteForce) {
  // An uneven mesh: a sphere with a few stretched triangles, queried inside, outside and far away.
  Mesh m = test::make_sphere(2);
  for (std::size_t v = 0; v < m.num_vertices(); v += 7) m.positions[v] *= 1.3;
  ClosestPointIndex index(m);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int i = 0; i < 500; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const auto hit = index.closest(p);
    EXPECT_NEAR(hit.distance, brute_force(m, p), 1e-12) << i;
    EXPECT_NEAR((hit.point - p).norm(), hit.distance, 1e-12);
  }
  const Vec3 far(100, -50, 3);
  EXPECT_NEAR(index.closest(far).distance, brute_force(m, far), 1e-9);
}
