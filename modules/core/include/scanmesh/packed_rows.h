#pragma once
// Rows of indices in about half the memory of an Adjacency: a row whose indices all lie within 32767 of
// an anchor (usually the row's own index) stores them as 16-bit differences from it; any other row stores
// them whole, in two 16-bit units each. On meshes in a spatial order (the denoiser's) nearly every row of
// face or vertex neighbours is of the first kind, so the table costs 2 bytes per index instead of 4; the
// neighbourhood table was the largest thing the denoiser holds.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "scanmesh/topology.h"

namespace scanmesh {

class PackedRows {
 public:
  /// Appends a row of indices `[first, last)` (each >= 0), to be read back with the same `anchor`.
  void append(int anchor, const int* first, const int* last);
  /// Appends rows[0..count), row r anchored at first_anchor + r: the same table as appending them one by
  /// one, packed in parallel.
  void append_rows(int first_anchor, const std::vector<int>* rows, std::size_t count);
  /// Room for `rows` rows of `units` 16-bit units in all (one per index in rows of the first kind).
  void reserve(std::size_t rows, std::size_t units) {
    starts_.reserve(rows + 1);
    units_.reserve(units);
  }
  /// The rows of `a`, each anchored at its own row index.
  static PackedRows from(const Adjacency& a);

  [[nodiscard]] std::size_t rows() const { return starts_.size() - 1; }
  [[nodiscard]] std::size_t entries() const { return entries_; }
  [[nodiscard]] std::size_t units() const { return units_.size(); }
  /// The longest row: a buffer of this many ints holds any row.
  [[nodiscard]] int max_row() const { return max_row_; }
  [[nodiscard]] std::size_t bytes() const { return starts_.size() * sizeof(std::uint32_t) + units_.size() * sizeof(std::uint16_t); }

  /// Calls f(index) for each index of row i (read with the anchor it was appended with), in order.
  template <class F>
  void for_each(std::size_t i, int anchor, F&& f) const {
    const std::uint32_t begin = starts_[i] & kOffset, end = starts_[i + 1] & kOffset;
    const std::uint16_t* u = units_.data() + begin;
    if ((starts_[i] & kWhole) == 0) {
      for (std::uint32_t k = 0; k < end - begin; ++k) f(anchor + static_cast<std::int16_t>(u[k]));
      return;
    }
    for (std::uint32_t k = 0; k < end - begin; k += 2) f(static_cast<int>(u[k] | static_cast<std::uint32_t>(u[k + 1]) << 16));
  }

  /// Row i's 16-bit differences from its anchor and their number, or nullptr if row i stores whole
  /// indices (read it with for_each or unpack then).
  [[nodiscard]] const std::uint16_t* differences(std::size_t i, int& count) const {
    if ((starts_[i] & kWhole) != 0) return nullptr;
    count = static_cast<int>((starts_[i + 1] & kOffset) - starts_[i]);
    return units_.data() + starts_[i];
  }

  /// Writes row i (read with the anchor it was appended with) to `out`, which holds max_row() ints;
  /// returns its length.
  int unpack(std::size_t i, int anchor, int* out) const {
    int n = 0;
    for_each(i, anchor, [out, &n](int j) { out[n++] = j; });
    return n;
  }

 private:
  static constexpr std::uint32_t kWhole = 0x80000000u;  ///< in starts_[i]: row i stores whole indices
  static constexpr std::uint32_t kOffset = 0x7FFFFFFFu;

  std::vector<std::uint32_t> starts_{0};  ///< row i is units_[starts_[i] & kOffset, starts_[i + 1] & kOffset)
  std::vector<std::uint16_t> units_;
  std::size_t entries_ = 0;
  int max_row_ = 0;
};

}  // namespace scanmesh
