#pragma once
// Figures as PNG bytes: histograms and flat-shaded views of meshes (with optional per-face colours,
// feature edges and coloured points). The only part of scanmesh that uses OpenCV.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "scanmesh/mesh.h"

namespace scanmesh::detail {

/// Binned values with their summary, as the sidecar stores them and a chart shows them.
struct Histogram {
  std::string name, title, unit;
  double lo = 0, hi = 1;
  std::vector<std::size_t> counts;
  double mean = 0, median = 0, p95 = 0, max = 0;
  std::size_t total = 0, clipped = 0;
};

/// Bins the finite values into `bins` bins over [lo, hi] (values beyond hi go into the last bin).
Histogram make_histogram(const std::string& name, const std::string& title, const std::string& unit, std::vector<double> values,
                         double lo, double hi, int bins);

/// Where a view looks from and what it frames.
struct Camera {
  Vec3 forward = Vec3(0, 0, -1);  ///< viewing direction (unit)
  Vec3 up = Vec3(0, 1, 0);        ///< up in the picture (unit, orthogonal to forward)
  Vec3 centre = Vec3::Zero();     ///< framed point (orthographic)
  double extent = 1.0;            ///< the framed width and height: scene units, or tangent units in perspective
  /// Perspective from `eye` (a sensor's view, as its image shows the scene); `centre_uv` is then the framed
  /// centre in tangent units (right, up).
  bool perspective = false;
  Vec3 eye = Vec3::Zero();
  double centre_u = 0.0, centre_v = 0.0;
};

/// A colour scale: values from lo (blue) to hi (red) through the turbo map; `unit` labels the bar.
struct ColourScale {
  double lo = 0, hi = 1;
  std::string unit;
};

/// One panel of a view figure.
struct Panel {
  const Mesh* mesh = nullptr;
  std::string title;
  std::vector<double> face_values;                        ///< coloured by `scale` when not empty
  std::vector<std::uint8_t> face_marked;                  ///< drawn red when set (flipped faces)
  std::vector<std::array<int, 2>> edges;                  ///< drawn dark (feature edges)
  const std::vector<Vec3>* points = nullptr;              ///< drawn as dots coloured by `point_values`
  const std::vector<double>* point_values = nullptr;
};

/// Panels side by side, each `size` pixels square, one colour bar below when a scale is given.
std::vector<unsigned char> render_views(const std::vector<Panel>& panels, const Camera& camera, int size,
                                        const std::optional<ColourScale>& scale);

/// A bar chart with axes, the mean, the median and the 95th percentile marked.
std::vector<unsigned char> render_histogram(const Histogram& h);

}  // namespace scanmesh::detail
