#pragma once
// Lengths that adapt to the data: an absolute value ("0.002"), a multiple of the cloud's mean
// nearest-neighbour spacing ("3*spacing"), a multiple of a mesh's mean edge length ("2*edge"), or a
// percentage of the bounding-box diagonal ("1%"). Defaults are in spacing units, so a user can give none.
#include <string>

namespace scanmesh {

struct Length {
  enum class Unit { absolute, spacing, edge, percent_of_diagonal };
  double value = 0.0;
  Unit unit = Unit::absolute;

  static Length absolute(double v) { return {v, Unit::absolute}; }
  static Length spacings(double v) { return {v, Unit::spacing}; }

  /// The length in scene units. `spacing`, `edge` and `diagonal` describe the data at hand.
  [[nodiscard]] double resolve(double spacing, double edge, double diagonal) const;
  [[nodiscard]] std::string str() const;
};

/// Parses "0.01", "3*spacing", "2*edge", "1%". Throws UsageError naming `what` and the accepted forms.
Length parse_length(const std::string& text, const std::string& what);

}  // namespace scanmesh
