#include "scanmesh/neighbourhoods.h"

#include <gtest/gtest.h>

#include <random>

#include "scanmesh/parallel.h"

using namespace scanmesh;

TEST(Neighbourhoods, RadiusSearchMatchesBruteForce) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> pts(2000);
  for (auto& p : pts) p = Vec3(u(rng), u(rng), u(rng));
  const double r = 0.08;
  const Adjacency a = radius_neighbourhoods(pts, r);
  ASSERT_EQ(a.rows(), pts.size());
  for (std::size_t i = 0; i < pts.size(); i += 13) {
    std::vector<int> expected;
    for (std::size_t j = 0; j < pts.size(); ++j)
      if ((pts[i] - pts[j]).squaredNorm() <= r * r) expected.push_back(static_cast<int>(j));
    EXPECT_EQ(std::vector<int>(a.begin(i), a.end(i)), expected) << i;
  }
}

TEST(Neighbourhoods, IndependentOfThreadCount) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> pts(3000);
  for (auto& p : pts) p = Vec3(u(rng), u(rng), u(rng));
  set_thread_count(1);
  const Adjacency one = radius_neighbourhoods(pts, 0.07);
  set_thread_count(2);
  const Adjacency two = radius_neighbourhoods(pts, 0.07);
  set_thread_count(0);
  EXPECT_EQ(one.offsets, two.offsets);
  EXPECT_EQ(one.indices, two.indices);
}

TEST(Neighbourhoods, MeanNearestNeighbourDistanceOfAGrid) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) pts.emplace_back(0.5 * i, 0.5 * j, 0.0);
  EXPECT_NEAR(mean_nearest_neighbour_distance(pts), 0.5, 1e-12);
  EXPECT_EQ(mean_nearest_neighbour_distance({Vec3(1, 2, 3)}), 0.0);
}

TEST(Neighbourhoods, MeanNearestNeighbourDistanceOfABigCloudFromASample) {
  // Over a million points the mean comes from a sample of them; on a jittered 1100 x 1000 grid it stays
  // within 0.5% of the mean over every point (the exact nearest neighbours).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::vector<Vec3> pts;
  for (int j = 0; j < 1000; ++j)
    for (int i = 0; i < 1100; ++i) pts.emplace_back(i + jitter(rng), j + jitter(rng), jitter(rng));
  const Adjacency nn = knn_neighbourhoods(pts, 1);
  double sum = 0.0;
  for (std::size_t i = 0; i < pts.size(); ++i) sum += (pts[static_cast<std::size_t>(*nn.begin(i))] - pts[i]).norm();
  const double exact = sum / static_cast<double>(pts.size());
  EXPECT_NEAR(mean_nearest_neighbour_distance(pts), exact, 0.005 * exact);
}
