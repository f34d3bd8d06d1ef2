#pragma once
// Exact closest points on a triangle mesh, accelerated by an R-tree over the faces' bounding boxes.
#include <memory>
#include <vector>

#include "scanmesh/mesh.h"

namespace scanmesh {

/// Closest point on triangle (a, b, c) to p (exact, handles degenerate triangles).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Answers "which point of the surface is closest to p" exactly (ties: the lowest face index). A query
/// visits the faces' bounding boxes nearest first and stops at the first box farther than the closest
/// face found; long, thin or overlapping faces cost only the queries that come near them.
class ClosestPointIndex {
 public:
  explicit ClosestPointIndex(const Mesh& surface);
  ~ClosestPointIndex();
  ClosestPointIndex(const ClosestPointIndex&) = delete;
  ClosestPointIndex& operator=(const ClosestPointIndex&) = delete;

  struct Hit {
    double distance = 0.0;
    int face = -1;
    Vec3 point = Vec3::Zero();
  };
  /// Thread-safe (const).
  [[nodiscard]] Hit closest(const Vec3& p) const;
  /// closest() for each query, in parallel; queries at one position are answered once (a mesh's copies
  /// of a vertex or face, which could each cost a scan of every overlapping face).
  [[nodiscard]] std::vector<Hit> closest_all(const std::vector<Vec3>& queries) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scanmesh
