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

TEST(PackedRows, RowsAppendedTogetherEqualRowsAppendedOneByOne) {
  // Blocks of rows anchored at their own index, near and far ones mixed, appended after a first row
  // and block by block: the same table, unit for unit, as one append per row.
  std::mt19937 rng(11);
  std::vector<std::vector<int>> rows(5000);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const int len = static_cast<int>(rng() % 12);
    for (int k = 0; k < len; ++k) rows[i].push_back(std::max(0, static_cast<int>(i) - 300 + static_cast<int>(rng() % 600)));
    if (rng() % 20 == 0) rows[i].push_back(static_cast<int>(rng() % 5000000));
  }
  PackedRows one, blocks;
  for (std::size_t i = 0; i < rows.size(); ++i) one.append(static_cast<int>(i), rows[i].data(), rows[i].data() + rows[i].size());
  blocks.append(0, rows[0].data(), rows[0].data() + rows[0].size());
  for (std::size_t start = 1; start < rows.size(); start += 1234)
    blocks.append_rows(static_cast<int>(start), rows.data() + start, std::min<std::size_t>(1234, rows.size() - start));
  ASSERT_EQ(blocks.rows(), one.rows());
  EXPECT_EQ(blocks.units(), one.units());
  EXPECT_EQ(blocks.entries(), one.entries());
  EXPECT_EQ(blocks.max_row(), one.max_row());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(row_of(blocks, i, static_cast<int>(i)), rows[i]) << "row " << i;
    int n1 = -1, n2 = -1;
    EXPECT_EQ(blocks.differences(i, n1) == nullptr, one.differences(i, n2) == nullptr) << "row " << i;
  }
}
