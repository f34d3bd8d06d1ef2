#include "scanmesh/packed_rows.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <vector>

using namespace scanmesh;

namespace {

std::vector<int> row_of(const PackedRows& p, std::size_t i, int anchor) {
  std::vector<int> out(static_cast<std::size_t>(p.max_row()));
  out.resize(static_cast<std::size_t>(p.unpack(i, anchor, out.data())));
  return out;
}

}  // namespace

TEST(PackedRows, GiveBackEveryRowNearAndFar) {
  // Rows near their anchor (16-bit differences, both signs, right up to the limits), rows that reach
  // too far (kept whole), empty rows, and indices near the top of the int range.
  const std::vector<std::vector<int>> rows = {
      {},
      {100000 - 32768, 100000, 100000 + 32767},  // the limits of a 16-bit difference
      {100000 - 32769, 100000},                  // one past: whole
      {0, 5, 7},
      {2147483000, 2147483647},
      {},
      {1, 70000}};
  const std::vector<int> anchors = {0, 100000, 100000, 3, 2147483600, 9, 5};
  PackedRows p;
  for (std::size_t i = 0; i < rows.size(); ++i) p.append(anchors[i], rows[i].data(), rows[i].data() + rows[i].size());
  ASSERT_EQ(p.rows(), rows.size());
  EXPECT_EQ(p.entries(), 12u);
  EXPECT_EQ(p.max_row(), 3);
  // Near rows: one unit per index; whole rows (the third, the last): two.
  EXPECT_EQ(p.units(), 3u + 2u * 2 + 3u + 2u + 2u * 2);
  for (std::size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(row_of(p, i, anchors[i]), rows[i]) << "row " << i;
}

TEST(PackedRows, MatchesTheAdjacencyItPacks) {
  // Random rows around their own index, a few with far members: the packed table reads back as the
  // plain one, and is about half its size when few rows reach far.
  std::mt19937 rng(3);
  Adjacency a;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    std::vector<int> row;
    const int len = static_cast<int>(rng() % 20);
    for (int k = 0; k < len; ++k) row.push_back(std::max(0, i - 500 + static_cast<int>(rng() % 1000)));
    if (rng() % 50 == 0) row.push_back(static_cast<int>(rng() % 10000000));
    a.indices.insert(a.indices.end(), row.begin(), row.end());
    a.offsets.push_back(static_cast<int>(a.indices.size()));
  }
  const PackedRows p = PackedRows::from(a);
  ASSERT_EQ(p.rows(), a.rows());
  EXPECT_EQ(p.entries(), a.indices.size());
  for (std::size_t i = 0; i < a.rows(); ++i)
    ASSERT_EQ(row_of(p, i, static_cast<int>(i)), std::vector<int>(a.begin(i), a.end(i))) << "row " << i;
  const std::size_t plain = (a.offsets.size() + a.indices.size()) * sizeof(int);
  EXPECT_LT(p.bytes(), 0.6 * static_cast<double>(plain));
}
