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

TEST(ClosestPoint, FacesSharingACentroidAreAllConsidered) {
  // A sphere, 300 copies of one of its faces (some with the corners in another order or their own
  // vertices), and 40 different triangles sharing another face's centroid (turned about it): the index
  // groups faces by centroid, and must still find the closest face, the lowest index of equally close
  // copies, as a brute-force search does. Queries at one position (closest_all) answered alike.
  Mesh m = test::make_sphere(2);
  const std::size_t nf = m.num_faces();
  const Face copied = m.faces[5];
  for (int k = 0; k < 300; ++k) {
    if (k % 3 == 0) {
      m.faces.push_back({copied[1], copied[2], copied[0]});
    } else if (k % 3 == 1) {
      const int base = static_cast<int>(m.num_vertices());
      for (int c = 0; c < 3; ++c) m.positions.push_back(m.positions[copied[c]]);
      m.faces.push_back({base, base + 1, base + 2});
    } else {
      m.faces.push_back(copied);
    }
  }
  const Face turned = m.faces[40];
  const Vec3 centre = (m.positions[turned[0]] + m.positions[turned[1]] + m.positions[turned[2]]) / 3.0;
  const Vec3 axis = (centre).normalized();
  for (int k = 1; k <= 40; ++k) {
    const Eigen::AngleAxisd spin(0.15 * k, axis);
    const int base = static_cast<int>(m.num_vertices());
    for (int c = 0; c < 3; ++c) m.positions.push_back(centre + spin * (m.positions[turned[c]] - centre));
    m.faces.push_back({base, base + 1, base + 2});
  }
  ClosestPointIndex index(m);
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<Vec3> queries;
  for (int i = 0; i < 400; ++i) queries.emplace_back(u(rng), u(rng), u(rng));
  for (int i = 0; i < 50; ++i) queries.push_back(m.positions[copied[0]] * (1.0 + 0.002 * i));
  for (int i = 0; i < 50; ++i) queries.push_back(centre * (1.0 + 0.002 * i));
  queries.insert(queries.end(), 30, centre);
  const std::vector<ClosestPointIndex::Hit> all = index.closest_all(queries);
  ASSERT_EQ(all.size(), queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const Vec3& p = queries[i];
    const auto hit = index.closest(p);
    EXPECT_NEAR(hit.distance, brute_force(m, p), 1e-12) << i;
    EXPECT_EQ(all[i].face, hit.face);
    EXPECT_EQ(all[i].distance, hit.distance);
    // The lowest index among the faces at that distance.
    for (std::size_t f = 0; f < static_cast<std::size_t>(hit.face); ++f) {
      const Face& t = m.faces[f];
      EXPECT_GT((closest_point_on_triangle(p, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]) - p).norm(), hit.distance)
          << i << " face " << f;
    }
    if (hit.face >= static_cast<int>(nf) && hit.face < static_cast<int>(nf) + 300) ADD_FAILURE() << "a copy of face 5 beat face 5 itself";
  }
}

TEST(ClosestPoint, LongThinFacesMatchBruteForce) {
  // A fan of 2,000 spokes (every face long and thin, every box overlapping its neighbours') and a few
  // needles across it: queries on and off the fan, at the centre every face is at distance 0 and the
  // lowest index wins.
  Mesh m;
  const int n = 2000;
  m.positions.emplace_back(0, 0, 0);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * i / n;
    m.positions.emplace_back(std::cos(a), std::sin(a), 0.001 * std::sin(5 * a));
  }
  for (int i = 0; i < n; ++i) m.faces.push_back({0, 1 + i, 1 + (i + 1) % n});
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int k = 0; k < 50; ++k) {
    const int base = static_cast<int>(m.num_vertices());
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    m.positions.push_back(a);
    m.positions.push_back(b);
    m.positions.push_back(a + Vec3(1e-3, 0, 0));
    m.faces.push_back({base, base + 1, base + 2});
  }
  ClosestPointIndex index(m);
  std::vector<Vec3> queries(m.positions.begin(), m.positions.begin() + 200);
  for (int i = 0; i < 300; ++i) queries.emplace_back(u(rng), u(rng), 0.2 * u(rng));
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const Vec3& p = queries[i];
    const auto hit = index.closest(p);
    EXPECT_NEAR(hit.distance, brute_force(m, p), 1e-12) << i;
    int lowest = -1;
    for (std::size_t f = 0; f < m.num_faces() && lowest < 0; ++f) {
      const Face& t = m.faces[f];
      if ((closest_point_on_triangle(p, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]) - p).norm() == hit.distance) lowest = static_cast<int>(f);
    }
    EXPECT_EQ(hit.face, lowest) << i;
  }
  EXPECT_EQ(index.closest(Vec3(0, 0, 0)).face, 0);
}
