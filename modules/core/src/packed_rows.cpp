#include "scanmesh/packed_rows.h"

#include <algorithm>
#include <string>

#include "scanmesh/errors.h"

namespace scanmesh {

void PackedRows::append(int anchor, const int* first, const int* last) {
  const bool near = std::all_of(first, last, [anchor](int j) {
    const long d = static_cast<long>(j) - anchor;
    return d >= -32768 && d <= 32767;
  });
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

PackedRows PackedRows::from(const Adjacency& a) {
  PackedRows p;
  p.reserve(a.rows(), a.indices.size() + a.indices.size() / 16);
  for (std::size_t i = 0; i < a.rows(); ++i) p.append(static_cast<int>(i), a.begin(i), a.end(i));
  return p;
}

}  // namespace scanmesh
