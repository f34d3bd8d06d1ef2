#pragma once
// The k nearest of a fixed set of points to any query point, through an exact FLANN k-d tree built once.
#include <memory>
#include <vector>

#include "scanmesh/mesh.h"

namespace scanmesh {

class NearestPoints {
 public:
  /// Indexes `points` (a copy is kept in tree order, so `points` need not outlive the index).
  explicit NearestPoints(const std::vector<Vec3>& points);
  ~NearestPoints();
  NearestPoints(const NearestPoints&) = delete;
  NearestPoints& operator=(const NearestPoints&) = delete;

  /// The indices of the k points nearest to q, nearest first (fewer if there are fewer points; ties in
  /// the order the tree visits them, which depends only on the points). Thread-safe (const).
  void nearest(const Vec3& q, int k, std::vector<int>& out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scanmesh
