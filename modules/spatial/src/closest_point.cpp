#include "scanmesh/closest_point.h"

#include <algorithm>
#include <cmath>

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>

#include "scanmesh/geometry.h"
#include "scanmesh/point_cloud.h"

namespace scanmesh {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;

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
  using Point = bg::model::point<double, 3, bg::cs::cartesian>;
  using Box = bg::model::box<Point>;
  using Entry = std::pair<Box, int>;  // a face's bounding box and the face
  const Mesh& surface;
  // An R-tree over the faces' boxes, searched nearest box first until the boxes are farther than the
  // closest face found. (A k-d tree over face centroids, searched within the closest distance plus the
  // largest centroid-to-corner reach, scanned every face near a query as soon as one triangle was long:
  // a fan of 200,000 spokes against itself ran past a minute.) A triangle stored more than once is
  // entered once, its first face (the lowest index wins ties anyway).
  bgi::rtree<Entry, bgi::rstar<16>> tree;

  static std::vector<Entry> boxes(const Mesh& s) {
    std::vector<Entry> e;
    for (int f : distinct_triangles(s)) {
      const Face& t = s.faces[static_cast<std::size_t>(f)];
      Vec3 lo = s.positions[t[0]], hi = lo;
      for (int k = 1; k < 3; ++k) lo = lo.cwiseMin(s.positions[t[k]]), hi = hi.cwiseMax(s.positions[t[k]]);
      e.emplace_back(Box(Point(lo.x(), lo.y(), lo.z()), Point(hi.x(), hi.y(), hi.z())), f);
    }
    return e;
  }
  explicit Impl(const Mesh& s) : surface(s), tree(boxes(s)) {}  // packed (bulk) build
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
  const std::size_t n = impl_->tree.size();
  if (n == 0) return best;
  const Impl::Point q(p.x(), p.y(), p.z());
  // The k nearest boxes, k growing fourfold until the farthest of them lies beyond the closest face
  // found: then so does every other box. Equal distances are tested too (the lower face index wins a
  // tie), with a margin for rounding. (Boost's incremental nearest-first iterator was far slower.)
  std::vector<Impl::Entry> near;
  for (std::size_t k = 8;; k *= 4) {
    near.clear();
    impl_->tree.query(bgi::nearest(q, static_cast<unsigned>(std::min(k, n))), std::back_inserter(near));
    double farthest = 0.0;
    for (const Impl::Entry& e : near) {
      farthest = std::max(farthest, bg::comparable_distance(q, e.first));
      impl_->test(p, static_cast<std::size_t>(e.second), best);
    }
    if (near.size() >= n || farthest > best.distance * best.distance * (1.0 + 1e-12)) break;
  }
  return best;
}

std::vector<ClosestPointIndex::Hit> ClosestPointIndex::closest_all(const std::vector<Vec3>& queries) const {
  const std::vector<std::uint32_t> first = first_copies(queries);
  std::vector<Hit> hits(queries.size());
  const auto n = static_cast<long>(queries.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (long i = 0; i < n; ++i)
    if (first.empty() || first[static_cast<std::size_t>(i)] == static_cast<std::uint32_t>(i)) hits[i] = closest(queries[i]);
  if (!first.empty())
    for (std::size_t i = 0; i < hits.size(); ++i) hits[i] = hits[first[i]];  // first[i] <= i: already answered
  return hits;
}

}  // namespace scanmesh
