#include "scanmesh/neighbourhoods.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

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

TEST(Neighbourhoods, SpatiallyOrderedSearchGivesTheSameRowsAndCuts) {
  // Searched a group of close points at a time (spatially_ordered) or one point at a time: the same rows
  // and the same capped rows, except which of several equally distant points fill a capped row (the two
  // searches use differently built trees). A grid with many distances equal to the radius, a sphere's
  // points in slices, a far-off point, and 600 copies of one point (rows over the cap, candidates over
  // the group limit).
  std::vector<Vec3> pts;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) pts.emplace_back(0.05 * i, 0.05 * j, 0.0);
  std::mt19937 rng(8);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Vec3> sphere(4000);
  for (auto& p : sphere) p = Vec3(g(rng), g(rng), g(rng)).normalized() + Vec3(3.0, 0.0, 0.0);
  std::sort(sphere.begin(), sphere.end(), [](const Vec3& a, const Vec3& b) {
    return std::make_tuple(std::floor(a.x() * 8), std::floor(a.y() * 8), a.z()) < std::make_tuple(std::floor(b.x() * 8), std::floor(b.y() * 8), b.z());
  });
  pts.insert(pts.end(), sphere.begin(), sphere.end());
  pts.emplace_back(100.0, 100.0, 100.0);
  pts.insert(pts.end(), 600, Vec3(-1.0, -1.0, -1.0));
  for (int cap : {0, 128})
    for (double r : {0.1, 0.23}) {
      std::size_t cut_grouped = 0, cut_single = 0;
      const Adjacency grouped = radius_neighbourhoods(pts, r, cap, &cut_grouped, true);
      const Adjacency single = radius_neighbourhoods(pts, r, cap, &cut_single, false);
      EXPECT_EQ(cut_grouped, cut_single);
      EXPECT_EQ(cut_grouped, cap > 0 ? 600u : 0u);
      ASSERT_EQ(grouped.offsets, single.offsets) << cap << " " << r;
      std::size_t differ = 0;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const std::vector<int> a(grouped.begin(i), grouped.end(i)), b(single.begin(i), single.end(i));
        if (static_cast<int>(b.size()) < cap || cap == 0) {
          EXPECT_EQ(a, b) << "row " << i << ", cap " << cap << ", radius " << r;
          continue;
        }
        differ += a != b ? 1 : 0;
        // A capped row: the cap nearest, whichever of the equally distant ones.
        double farthest = 0.0;
        for (int j : a) farthest = std::max(farthest, (pts[j] - pts[i]).squaredNorm());
        for (std::size_t j = 0; j < pts.size(); ++j) {
          if (!std::binary_search(a.begin(), a.end(), static_cast<int>(j))) {
            EXPECT_GE((pts[j] - pts[i]).squaredNorm(), farthest);
          }
        }
      }
      EXPECT_LE(differ, cap > 0 ? 600u : 0u);
    }
}

TEST(Neighbourhoods, RowsAroundAPositionManyPointsShareAreTheNearestByIndex) {
  // 1,000 copies of one point inside a jittered grid, and 40 copies of another: the search runs over the
  // distinct positions (a k-d tree cannot split a shared position, so the per-point search was quadratic)
  // and each row must still be what the definition says. Uncapped: every point within the radius. Capped:
  // the cap nearest, equally distant ones by index with the point itself first; rows of points not near
  // the copies lose nothing. The same on one and two threads, grouped or not.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.01, 0.01);
  std::vector<Vec3> pts;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) {
      pts.emplace_back(0.05 * i + jitter(rng), 0.05 * j + jitter(rng), 0.0);
      if (i == 10 && j % 3 == 0)
        for (int c = 0; c < 100; ++c) pts.emplace_back(0.5, 0.5, 0.0);  // copies spread through the array
      if (i == 20 && j == 20)
        for (int c = 0; c < 40; ++c) pts.emplace_back(1.0, 1.0, 0.001);
    }
  const double r = 0.12;
  auto brute = [&](std::size_t i, int cap) {
    std::vector<std::tuple<double, bool, int>> all;
    for (std::size_t j = 0; j < pts.size(); ++j) {
      const double d2 = (pts[j] - pts[i]).squaredNorm();
      if (d2 <= r * r) all.emplace_back(d2, j != i, static_cast<int>(j));
    }
    std::sort(all.begin(), all.end());
    if (cap > 0 && all.size() > static_cast<std::size_t>(cap)) all.resize(static_cast<std::size_t>(cap));
    std::vector<int> row;
    for (const auto& a : all) row.push_back(std::get<2>(a));
    std::sort(row.begin(), row.end());
    return row;
  };
  for (int cap : {0, 128}) {
    std::size_t cut = 0;
    const Adjacency a = radius_neighbourhoods(pts, r, cap, &cut, false);
    std::size_t expected_cut = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const std::vector<int> want = brute(i, cap);
      expected_cut += cap > 0 && brute(i, 0).size() > static_cast<std::size_t>(cap) ? 1 : 0;
      ASSERT_EQ(std::vector<int>(a.begin(i), a.end(i)), want) << "row " << i << ", cap " << cap;
    }
    EXPECT_EQ(cut, expected_cut);
    if (cap > 0) {
      EXPECT_GT(cut, 1000u);
    }
    for (int threads : {1, 2})
      for (bool grouped : {false, true}) {
        set_thread_count(threads);
        std::size_t cut2 = 0;
        const Adjacency b = radius_neighbourhoods(pts, r, cap, &cut2, grouped);
        EXPECT_EQ(b.offsets, a.offsets) << threads << " " << grouped;
        EXPECT_EQ(b.indices, a.indices) << threads << " " << grouped;
        EXPECT_EQ(cut2, cut);
        const PackedRows packed = packed_radius_neighbourhoods(pts, r, cap, nullptr, grouped);
        std::vector<int> row(static_cast<std::size_t>(packed.max_row()));
        for (std::size_t i = 0; i < pts.size(); i += 7) {
          const int len = packed.unpack(i, static_cast<int>(i), row.data());
          EXPECT_EQ(std::vector<int>(row.begin(), row.begin() + len), std::vector<int>(a.begin(i), a.end(i)));
        }
      }
    set_thread_count(0);
  }
}
