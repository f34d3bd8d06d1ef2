#include "scanmesh/packed_rows.h"

#include <algorithm>
#include <cstdlib>
#include <string>

#include "scanmesh/errors.h"

namespace scanmesh {

namespace {

// True if every index of [first, last) lies within a 16-bit difference of `anchor`.
bool near_anchor(int anchor, const int* first, const int* last) {
  return std::all_of(first, last, [anchor](int j) {
    const long d = static_cast<long>(j) - anchor;
    return d >= -32768 && d <= 32767;
  });
}

}  // namespace

void PackedRows::append(int anchor, const int* first, const int* last) {
  const bool near = near_anchor(anchor, first, last);
  if (near) {
    for (const int* p = first; p != last; ++p) units_.push_back(static_cast<std::uint16_t>(static_cast<std::int16_t>(*p - anchor)));
  } else {
    starts_.back() |= kWhole;
    for (const int* p = first; p != last; ++p) {
      const auto j = static_cast<std::uint32_t>(*p);
      units_.push_back(static_cast<std::uint16_t>(j & 0xFFFFu));
      units_.push_back(static_cast<std::uint16_t>(j >> 16));
    }
  }
  if (units_.size() > kOffset)
    throw InputError("neighbourhood table too large: " + std::to_string(units_.size()) + " 16-bit units (at most 2^31)");
  starts_.push_back(static_cast<std::uint32_t>(units_.size()));
  const auto n = static_cast<std::size_t>(last - first);
  entries_ += n;
  max_row_ = std::max(max_row_, static_cast<int>(n));
}

void PackedRows::append_rows(int first_anchor, const std::vector<int>* rows, std::size_t count) {
  // Each row's size in units (negative: whole indices) first, then the starts, then the units, each
  // row written by whichever thread has it.
  const std::size_t first_start = starts_.size() - 1;
  starts_.resize(first_start + count + 1);
  const auto n = static_cast<long>(count);
  std::vector<long> size(count);
#pragma omp parallel for schedule(static)
  for (long r = 0; r < n; ++r) {
    const std::vector<int>& row = rows[r];
    const auto len = static_cast<long>(row.size());
    size[r] = near_anchor(first_anchor + static_cast<int>(r), row.data(), row.data() + row.size()) ? len : -2 * len;
  }
  std::size_t at = units_.size(), added = 0;
  for (std::size_t r = 0; r < count; ++r) {
    const std::size_t units = static_cast<std::size_t>(std::abs(size[r]));
    if (at + units > kOffset)
      throw InputError("neighbourhood table too large: " + std::to_string(at + units) + " 16-bit units (at most 2^31)");
    if (size[r] < 0) starts_[first_start + r] |= kWhole;
    at += units;
    starts_[first_start + r + 1] = static_cast<std::uint32_t>(at);
    added += rows[r].size();
    max_row_ = std::max(max_row_, static_cast<int>(rows[r].size()));
  }
  entries_ += added;
  units_.resize(at);
#pragma omp parallel for schedule(static)
  for (long r = 0; r < n; ++r) {
    const int anchor = first_anchor + static_cast<int>(r);
    std::uint16_t* u = units_.data() + (starts_[first_start + static_cast<std::size_t>(r)] & kOffset);
    if (size[r] >= 0) {
      for (int j : rows[r]) *u++ = static_cast<std::uint16_t>(static_cast<std::int16_t>(j - anchor));
    } else {
      for (int j : rows[r]) {
        const auto w = static_cast<std::uint32_t>(j);
        *u++ = static_cast<std::uint16_t>(w & 0xFFFFu);
        *u++ = static_cast<std::uint16_t>(w >> 16);
      }
    }
  }
}

PackedRows PackedRows::from(const Adjacency& a) {
  PackedRows p;
  p.reserve(a.rows(), a.indices.size() + a.indices.size() / 16);
  for (std::size_t i = 0; i < a.rows(); ++i) p.append(static_cast<int>(i), a.begin(i), a.end(i));
  return p;
}

}  // namespace scanmesh
