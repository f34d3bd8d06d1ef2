#include "scanmesh/normal_filtering.h"

#include <algorithm>
#include <cmath>

#include "scanmesh/neighbourhoods.h"

namespace scanmesh {

double robust_weight(RobustEstimator estimator, double x, double s) {
  switch (estimator) {
    case RobustEstimator::tukey: {
      if (x > s) return 0.0;
      const double u = 1.0 - (x * x) / (s * s);
      return 0.5 * u * u;
    }
    case RobustEstimator::gaussian: return std::exp(-(x * x) / (2.0 * s * s));
    case RobustEstimator::huber: return x <= s ? 1.0 : s / x;
    case RobustEstimator::lorentzian: return 1.0 / (1.0 + (x * x) / (2.0 * s * s));
  }
  return 0.0;
}

namespace {

// The estimator is a template parameter so the hot loop has no switch in it.
template <RobustEstimator E>
void filter_impl(const FaceGeometry& g, const Adjacency& nbh, double sigma_c, double sigma_s,
                 std::vector<Vec3>& out) {
  const auto nf = static_cast<long>(g.normals.size());
  const double inv_two_sc2 = 1.0 / (2.0 * sigma_c * sigma_c);
  const double inv_ss2 = 1.0 / (sigma_s * sigma_s);
  const double ss2 = sigma_s * sigma_s;
  const double inv_two_ss2 = 1.0 / (2.0 * sigma_s * sigma_s);
#pragma omp parallel for schedule(dynamic, 512)
  for (long i = 0; i < nf; ++i) {
    const Vec3& ni = g.normals[i];
    const Vec3& ci = g.centroids[i];
    Vec3 sum = Vec3::Zero();
    for (const int* j = nbh.begin(i); j != nbh.end(i); ++j) {
      const double aj = g.areas[*j];
      if (aj == 0.0) continue;
      const Vec3& nj = g.normals[*j];
      const double x2 = (ni - nj).squaredNorm();
      double w;
      if constexpr (E == RobustEstimator::tukey) {
        if (x2 > ss2) continue;
        const double u = 1.0 - x2 * inv_ss2;
        w = 0.5 * u * u;
      } else if constexpr (E == RobustEstimator::gaussian) {
        w = std::exp(-x2 * inv_two_ss2);
      } else if constexpr (E == RobustEstimator::huber) {
        w = x2 <= ss2 ? 1.0 : sigma_s / std::sqrt(x2);
      } else {
        w = 1.0 / (1.0 + x2 * inv_two_ss2);
      }
      const double d2 = (ci - g.centroids[*j]).squaredNorm();
      sum += (aj * std::exp(-d2 * inv_two_sc2) * w) * nj;
    }
    const double len = sum.norm();
    out[i] = len > 0.0 ? Vec3(sum / len) : ni;
  }
}

}  // namespace

void filter_face_normals(const FaceGeometry& geometry, const Adjacency& neighbourhoods, double sigma_c,
                         double sigma_s, RobustEstimator estimator, std::vector<Vec3>& filtered) {
  filtered.resize(geometry.normals.size());
  switch (estimator) {
    case RobustEstimator::tukey: filter_impl<RobustEstimator::tukey>(geometry, neighbourhoods, sigma_c, sigma_s, filtered); break;
    case RobustEstimator::gaussian: filter_impl<RobustEstimator::gaussian>(geometry, neighbourhoods, sigma_c, sigma_s, filtered); break;
    case RobustEstimator::huber: filter_impl<RobustEstimator::huber>(geometry, neighbourhoods, sigma_c, sigma_s, filtered); break;
    case RobustEstimator::lorentzian: filter_impl<RobustEstimator::lorentzian>(geometry, neighbourhoods, sigma_c, sigma_s, filtered); break;
  }
}

double mean_centroid_distance(const Mesh& mesh, const Topology& topology, const FaceGeometry& geometry) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t e = 0; e < topology.edges.size(); ++e) {
    const int* f = topology.edge_faces.begin(e);
    const int count = topology.edge_faces.size(e);
    for (int a = 0; a < count; ++a)
      for (int b = a + 1; b < count; ++b) {
        sum += (geometry.centroids[f[a]] - geometry.centroids[f[b]]).norm();
        ++n;
      }
  }
  if (n > 0) return sum / static_cast<double>(n);
  return mean_edge_length(mesh, topology);
}

Adjacency face_neighbourhoods(const Topology& topology, const FaceGeometry& geometry, double radius,
                              NeighbourhoodKind kind) {
  if (kind == NeighbourhoodKind::ball) return radius_neighbourhoods(geometry.centroids, radius);

  // Connected ball: grow from face i through edge-adjacent faces whose centroids are within the radius.
  const auto nf = static_cast<long>(geometry.centroids.size());
  std::vector<std::vector<int>> rows(geometry.centroids.size());
  const double r2 = radius * radius;
#pragma omp parallel
  {
    std::vector<int> stack;
    std::vector<int> seen;  // small: linear search is faster than a set
#pragma omp for schedule(dynamic, 256)
    for (long i = 0; i < nf; ++i) {
      seen.assign(1, static_cast<int>(i));
      stack.assign(1, static_cast<int>(i));
      while (!stack.empty()) {
        const int f = stack.back();
        stack.pop_back();
        for (const int* g = topology.face_faces.begin(f); g != topology.face_faces.end(f); ++g) {
          if (std::find(seen.begin(), seen.end(), *g) != seen.end()) continue;
          if ((geometry.centroids[*g] - geometry.centroids[i]).squaredNorm() > r2) continue;
          seen.push_back(*g);
          stack.push_back(*g);
        }
      }
      std::sort(seen.begin(), seen.end());
      rows[i] = seen;
    }
  }
  Adjacency a;
  a.offsets.assign(rows.size() + 1, 0);
  for (std::size_t i = 0; i < rows.size(); ++i) a.offsets[i + 1] = a.offsets[i] + static_cast<int>(rows[i].size());
  a.indices.reserve(static_cast<std::size_t>(a.offsets.back()));
  for (const auto& r : rows) a.indices.insert(a.indices.end(), r.begin(), r.end());
  return a;
}

}  // namespace scanmesh
