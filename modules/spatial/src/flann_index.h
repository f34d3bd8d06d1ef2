#pragma once
// The one place FLANN is included. An exact k-d tree (single tree, unlimited checks) over 3D points.
#include <flann/flann.hpp>
#include <vector>

#include "scanmesh/mesh.h"

namespace scanmesh::detail {

class PointTree {
 private:
  // flann::RadiusResultSet's test, appending the indices straight to the caller's vector (no distances
  // kept, nothing allocated per query once `out` has grown).
  class IndicesWithin : public flann::ResultSet<double> {
   public:
    IndicesWithin(double squared_radius, std::vector<std::size_t>& out) : r2_(squared_radius), out_(out) {}
    bool full() const override { return true; }
    void addPoint(double dist, std::size_t index) override {
      if (dist < r2_) out_.push_back(index);
    }
    double worstDist() const override { return r2_; }

   private:
    double r2_;
    std::vector<std::size_t>& out_;
  };

  // Single queries go straight to the tree: flann::Index's knnSearch and radiusSearch open an OpenMP
  // parallel region on every call, and called once per point inside our own parallel loops that cost
  // two million futex system calls (passive waiting) while reading a 700k-point cloud.
  static const flann::SearchParams& single_query() {
    static const flann::SearchParams p = [] {
      flann::SearchParams q(flann::FLANN_CHECKS_UNLIMITED);
      q.sorted = false;
      return q;
    }();
    return p;
  }

 public:
  /// With `copy` the tree keeps its own copy of the points in tree order (faster queries on points in any
  /// order); without, it reads `points` in place (24 bytes per point less; as fast when the points are
  /// already in a spatial order, like the denoiser's faces). `points` must outlive the tree either way.
  /// `leaf_size`: points per leaf; larger leaves build faster and suit queries that gather many points.
  explicit PointTree(const std::vector<Vec3>& points, bool copy = true, int leaf_size = 12)
      : data_(points.empty() ? nullptr : const_cast<double*>(points.data()->data()), points.size(), 3),
        index_(data_, flann::KDTreeSingleIndexParams(leaf_size, copy)) {
    if (!points.empty()) index_.buildIndex();
  }

  /// Indices within `radius` of q (unsorted).
  void radius(const Vec3& q, double radius, std::vector<std::size_t>& out) const {
    out.clear();
    if (data_.rows == 0) return;
    IndicesWithin found(static_cast<float>(radius * radius), out);
    index_.findNeighbors(found, q.data(), single_query());
  }

  /// A radius search to run many times, one per thread: search() puts the points within `radius` of q,
  /// or only the `max_neighbours` nearest of them (max_neighbours > 0), into `out` (unsorted). The result
  /// set and `out` are reused, so a loop of queries allocates nothing once they have grown. FLANN compares
  /// in float: callers that need an exact radius search a little wider and test the distances themselves.
  class Nearest {
   public:
    Nearest(double radius, int max_neighbours)
        : capped_(static_cast<float>(radius * radius), max_neighbours > 0 ? static_cast<std::size_t>(max_neighbours) : 1),
          all_(static_cast<float>(radius * radius), all_out_), limit_(max_neighbours) {}
    void search(const PointTree& tree, const Vec3& q, std::vector<std::size_t>& out) {
      out.clear();
      if (tree.data_.rows == 0) return;
      if (limit_ <= 0) {
        all_out_.clear();
        tree.index_.findNeighbors(all_, q.data(), single_query());
        out.swap(all_out_);
        return;
      }
      capped_.clear();
      tree.index_.findNeighbors(capped_, q.data(), single_query());
      out.resize(capped_.size());
      dist_.resize(capped_.size());
      if (!out.empty()) capped_.copy(out.data(), dist_.data(), out.size(), false);
    }
    /// The squared distances of the last capped search's points, in the order of `out`.
    [[nodiscard]] const std::vector<double>& distances() const { return dist_; }

   private:
    flann::KNNRadiusResultSet<double> capped_;
    std::vector<std::size_t> all_out_;
    IndicesWithin all_;
    std::vector<double> dist_;
    int limit_;
  };

  /// The k nearest indices to q, nearest first, with squared distances.
  void knn(const Vec3& q, std::size_t k, std::vector<std::size_t>& idx_out, std::vector<double>& dist_out) const {
    idx_out.clear();
    dist_out.clear();
    if (data_.rows == 0) return;
    k = std::min<std::size_t>(k, data_.rows);
    // The result sets flann::Index::knnSearch would use (a heap above 250 neighbours), same results.
    auto take = [&](auto& found) {
      index_.findNeighbors(found, q.data(), single_query());
      const std::size_t n = std::min(found.size(), k);
      idx_out.resize(n);
      dist_out.resize(n);
      if (n > 0) found.copy(idx_out.data(), dist_out.data(), n, true);
    };
    if (k > 250) {
      flann::KNNResultSet2<double> found(k);
      take(found);
    } else {
      flann::KNNSimpleResultSet<double> found(k);
      take(found);
    }
  }

 private:
  flann::Matrix<double> data_;
  mutable flann::KDTreeSingleIndex<flann::L2_Simple<double>> index_;
};

}  // namespace scanmesh::detail
