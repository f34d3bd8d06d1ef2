#include "scanmesh/nearest_points.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

using namespace scanmesh;

TEST(NearestPoints, TheKNearestComeNearestFirst) {
  std::vector<Vec3> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(i, 0, 0);
  const NearestPoints index(line);
  std::vector<int> near;
  index.nearest(Vec3(3.2, 0.5, 0), 3, near);
  EXPECT_EQ(near, (std::vector<int>{3, 4, 2}));
  index.nearest(Vec3(-5, 0, 0), 20, near);  // more asked than there are: all of them, by distance
  ASSERT_EQ(near.size(), 10u);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(near[i], i);
}

TEST(NearestPoints, AgreesWithABruteForceSearch) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec3> points(500);
  for (auto& p : points) p = Vec3(u(rng), u(rng), u(rng));
  const NearestPoints index(points);
  std::vector<int> near;
  for (int q = 0; q < 50; ++q) {
    const Vec3 query(u(rng), u(rng), u(rng));
    index.nearest(query, 8, near);
    std::vector<std::pair<double, int>> all;
    for (int i = 0; i < 500; ++i) all.emplace_back((points[i] - query).squaredNorm(), i);
    std::sort(all.begin(), all.end());
    ASSERT_EQ(near.size(), 8u);
    for (int k = 0; k < 8; ++k) EXPECT_EQ(near[k], all[k].second);
  }
}

TEST(NearestPoints, AnEmptySetHasNoNeighbours) {
  const NearestPoints index(std::vector<Vec3>{});
  std::vector<int> near{1, 2};
  index.nearest(Vec3::Zero(), 4, near);
  EXPECT_TRUE(near.empty());
}
