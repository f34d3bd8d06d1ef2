#include "scanmesh/closest_point.h"

#include <algorithm>
#include <cmath>

#include "flann_index.h"
#include "scanmesh/geometry.h"
#include "scanmesh/point_cloud.h"

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
  // The tree's points: the faces' centroids, one per face (`faces_at` empty: tree point i is face i).
  // Where a triangle is stored more than once only its first face is kept (the lowest index wins ties
  // anyway), and where many faces share a centroid the tree holds the distinct centroids, each with its
  // faces in `faces_at` (ascending): a k-d tree cannot split a position many points share, and every
  // query near them scanned them all.
  std::vector<Vec3> centroids;
  std::vector<int> faces_start, faces_at;
  std::vector<double> reach;  // per tree point: max distance from it to its faces' corners
  double max_reach = 0.0;
  std::unique_ptr<detail::PointTree> tree;

  explicit Impl(const Mesh& s) : surface(s) {
    const std::vector<int> faces = distinct_triangles(s);
    centroids.resize(faces.size());
    for (std::size_t i = 0; i < faces.size(); ++i) centroids[i] = face_centroid(s.positions, s.faces[static_cast<std::size_t>(faces[i])]);
    if (const std::vector<std::uint32_t> first = first_copies(centroids, 17); !first.empty()) {
      std::vector<int> point(faces.size()), count;
      std::vector<Vec3> distinct;
      for (std::size_t i = 0; i < faces.size(); ++i) {
        if (first[i] == i) {
          point[i] = static_cast<int>(distinct.size());
          distinct.push_back(centroids[i]);
          count.push_back(0);
        } else {
          point[i] = point[first[i]];
        }
        ++count[static_cast<std::size_t>(point[i])];
      }
      faces_start.assign(1, 0);
      for (int c : count) faces_start.push_back(faces_start.back() + c);
      faces_at.resize(faces.size());
      std::vector<int> fill(faces_start.begin(), faces_start.end() - 1);
      for (std::size_t i = 0; i < faces.size(); ++i) faces_at[static_cast<std::size_t>(fill[static_cast<std::size_t>(point[i])]++)] = faces[i];
      centroids.swap(distinct);
    } else if (faces.size() < s.num_faces()) {
      faces_start.resize(faces.size() + 1);
      for (std::size_t i = 0; i <= faces.size(); ++i) faces_start[i] = static_cast<int>(i);
      faces_at = faces;
    }
    reach.assign(centroids.size(), 0.0);
    for (std::size_t i = 0; i < centroids.size(); ++i) {
      for_faces(i, [&](std::size_t f) {
        for (int k = 0; k < 3; ++k) reach[i] = std::max(reach[i], (s.positions[s.faces[f][k]] - centroids[i]).norm());
      });
      max_reach = std::max(max_reach, reach[i]);
    }
    tree = std::make_unique<detail::PointTree>(centroids);
  }
  template <class F>
  void for_faces(std::size_t i, F&& f) const {
    if (faces_start.empty()) {
      f(i);
      return;
    }
    for (int k = faces_start[i]; k < faces_start[i + 1]; ++k) f(static_cast<std::size_t>(faces_at[static_cast<std::size_t>(k)]));
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
  impl_->tree->knn(p, 4, idx, d2);
  for (std::size_t i : idx) impl_->for_faces(i, [&](std::size_t f) { impl_->test(p, f, best); });
  // Any face closer than `best` has its centroid within best + reach(face) <= best + max_reach.
  const double bound = best.distance + impl_->max_reach;
  impl_->tree->radius(p, bound * 1.0001 + 1e-300, idx);
  for (std::size_t i : idx)
    if ((impl_->centroids[i] - p).norm() <= best.distance + impl_->reach[i] + 1e-12 * bound)
      impl_->for_faces(i, [&](std::size_t f) { impl_->test(p, f, best); });
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
