#include "scanmesh/nearest_points.h"

#include <algorithm>

#include "flann_index.h"

namespace scanmesh {

struct NearestPoints::Impl {
  explicit Impl(const std::vector<Vec3>& points) : tree(points, true) {}
  detail::PointTree tree;
};

NearestPoints::NearestPoints(const std::vector<Vec3>& points) : impl_(std::make_unique<Impl>(points)) {}
NearestPoints::~NearestPoints() = default;

void NearestPoints::nearest(const Vec3& q, int k, std::vector<int>& out) const {
  thread_local std::vector<std::size_t> idx;
  thread_local std::vector<double> d2;
  impl_->tree.knn(q, static_cast<std::size_t>(std::max(k, 0)), idx, d2);
  out.assign(idx.begin(), idx.end());
}

}  // namespace scanmesh
