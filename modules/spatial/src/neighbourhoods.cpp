#include "scanmesh/neighbourhoods.h"

#include <algorithm>

#include "flann_index.h"

namespace scanmesh {

Adjacency radius_neighbourhoods(const std::vector<Vec3>& points, double radius) {
  const auto n = static_cast<long>(points.size());
  detail::PointTree tree(points);
  std::vector<std::vector<int>> rows(points.size());
  const double r2 = radius * radius;
#pragma omp parallel
  {
    std::vector<std::size_t> found;
#pragma omp for schedule(dynamic, 256)
    for (long i = 0; i < n; ++i) {
      // FLANN takes the squared radius as float; search a little wider and decide in double.
      tree.radius(points[i], radius * 1.001, found);
      auto& row = rows[i];
      row.clear();
      for (std::size_t j : found)
        if ((points[j] - points[i]).squaredNorm() <= r2) row.push_back(static_cast<int>(j));
      std::sort(row.begin(), row.end());
    }
  }
  Adjacency a;
  a.offsets.resize(points.size() + 1);
  a.offsets[0] = 0;
  for (std::size_t i = 0; i < points.size(); ++i) a.offsets[i + 1] = a.offsets[i] + static_cast<int>(rows[i].size());
  a.indices.resize(static_cast<std::size_t>(a.offsets.back()));
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) std::copy(rows[i].begin(), rows[i].end(), a.indices.begin() + a.offsets[i]);
  return a;
}

double mean_nearest_neighbour_distance(const std::vector<Vec3>& points) {
  if (points.size() < 2) return 0.0;
  detail::PointTree tree(points);
  const auto n = static_cast<long>(points.size());
  std::vector<double> nearest(points.size(), 0.0);
#pragma omp parallel
  {
    std::vector<std::size_t> idx;
    std::vector<double> d2;
#pragma omp for schedule(dynamic, 256)
    for (long i = 0; i < n; ++i) {
      tree.knn(points[i], 2, idx, d2);
      double best = 0.0;
      for (std::size_t k = 0; k < idx.size(); ++k)
        if (idx[k] != static_cast<std::size_t>(i)) {
          best = std::sqrt(d2[k]);
          break;
        }
      nearest[i] = best;
    }
  }
  double sum = 0.0;  // fixed order: independent of the thread count
  for (double d : nearest) sum += d;
  return sum / static_cast<double>(points.size());
}

}  // namespace scanmesh
