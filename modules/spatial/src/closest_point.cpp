#include "scanmesh/closest_point.h"

#include <algorithm>
#include <cmath>

#include "flann_index.h"

namespace scanmesh {

// Region-based closest point on a triangle (Voronoi regions of vertices, edges, face), as in
// Ericson, "Real-Time Collision Detection", 5.1.5; degenerate triangles fall through to the edges.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double sum = va + vb + vc;
  if (sum > 0.0 && std::isfinite(sum)) {
    const double v = vb / sum, w = vc / sum;
    return a + v * ab + w * ac;
  }
  // Degenerate (collinear) triangle: the closest point lies on one of its edges.
  auto on_segment = [&p](const Vec3& s, const Vec3& t) {
    const Vec3 d = t - s;
    const double len2 = d.squaredNorm();
    const double u = len2 > 0.0 ? std::clamp((p - s).dot(d) / len2, 0.0, 1.0) : 0.0;
    return Vec3(s + u * d);
  };
  Vec3 best = on_segment(a, b);
  for (const Vec3& q : {on_segment(b, c), on_segment(c, a)})
    if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
  return best;
}

struct ClosestPointIndex::Impl {
  const Mesh& surface;
  std::vector<Vec3> centroids;
  std::vector<double> reach;  // max distance from a face's centroid to its corners
  double max_reach = 0.0;
  detail::PointTree tree;

  explicit Impl(const Mesh& s) : surface(s), centroids(make_centroids(s)), tree(centroids) {
    reach.resize(s.num_faces());
    for (std::size_t f = 0; f < s.num_faces(); ++f) {
      double r = 0.0;
      for (int k = 0; k < 3; ++k) r = std::max(r, (s.positions[s.faces[f][k]] - centroids[f]).norm());
      reach[f] = r;
      max_reach = std::max(max_reach, r);
    }
  }
  static std::vector<Vec3> make_centroids(const Mesh& s) {
    std::vector<Vec3> c(s.num_faces());
    for (std::size_t f = 0; f < s.num_faces(); ++f)
      c[f] = (s.positions[s.faces[f][0]] + s.positions[s.faces[f][1]] + s.positions[s.faces[f][2]]) / 3.0;
    return c;
  }
  void test(const Vec3& p, std::size_t f, Hit& best) const {
    const Face& t = surface.faces[f];
    const Vec3 q = closest_point_on_triangle(p, surface.positions[t[0]], surface.positions[t[1]], surface.positions[t[2]]);
    const double d = (q - p).norm();
    // Ties go to the lower face index so the answer does not depend on search order.
    if (best.face < 0 || d < best.distance || (d == best.distance && static_cast<int>(f) < best.face)) {
      best.distance = d;
      best.face = static_cast<int>(f);
      best.point = q;
    }
  }
};

ClosestPointIndex::ClosestPointIndex(const Mesh& surface) : impl_(std::make_unique<Impl>(surface)) {}
ClosestPointIndex::~ClosestPointIndex() = default;

ClosestPointIndex::Hit ClosestPointIndex::closest(const Vec3& p) const {
  Hit best;
  if (impl_->centroids.empty()) return best;
  std::vector<std::size_t> idx;
  std::vector<double> d2;
  impl_->tree.knn(p, 4, idx, d2);
  for (std::size_t f : idx) impl_->test(p, f, best);
  // Any face closer than `best` has its centroid within best + reach(face) <= best + max_reach.
  const double bound = best.distance + impl_->max_reach;
  impl_->tree.radius(p, bound * 1.0001 + 1e-300, idx);
  for (std::size_t f : idx)
    if ((impl_->centroids[f] - p).norm() <= best.distance + impl_->reach[f] + 1e-12 * bound) impl_->test(p, f, best);
  return best;
}

}  // namespace scanmesh
