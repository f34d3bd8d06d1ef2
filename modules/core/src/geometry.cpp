#include "scanmesh/geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "scanmesh/point_cloud.h"

namespace scanmesh {

Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c, double* area) {
  const Vec3 n = (b - a).cross(c - a);
  const double len = n.norm();
  if (area != nullptr) *area = 0.5 * len;
  if (!(len > 1e-300)) {
    if (area != nullptr) *area = 0.0;
    return Vec3::Zero();
  }
  return n / len;
}

void compute_face_geometry(const std::vector<Vec3>& positions, const std::vector<Face>& faces,
                           FaceGeometry& out, bool with_centroids) {
  const auto nf = static_cast<long>(faces.size());
  out.normals.resize(faces.size());
  out.areas.resize(faces.size());
  if (with_centroids) out.centroids.resize(faces.size());
  else std::vector<Vec3>().swap(out.centroids);
#pragma omp parallel for schedule(static)
  for (long f = 0; f < nf; ++f) {
    const Vec3& a = positions[faces[f][0]];
    const Vec3& b = positions[faces[f][1]];
    const Vec3& c = positions[faces[f][2]];
    out.normals[f] = triangle_normal(a, b, c, &out.areas[f]);
    if (with_centroids) out.centroids[f] = face_centroid(positions, faces[f]);
  }
}

double triangle_shape(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = (b - c).norm(), lb = (c - a).norm(), lc = (a - b).norm();
  const double twice_area = (b - a).cross(c - a).norm();
  const double shortest = std::min({la, lb, lc});
  if (!(twice_area > 0.0) || !(shortest > 0.0)) return std::numeric_limits<double>::infinity();
  return la * lb * lc / (2.0 * twice_area) / shortest;  // circumradius = abc / (4 area)
}

double mean_edge_length(const Mesh& mesh, const Topology& topology) {
  if (topology.edges.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& [a, b] : topology.edges) sum += (mesh.positions[a] - mesh.positions[b]).norm();
  return sum / static_cast<double>(topology.edges.size());
}

std::vector<Vec3> vertex_normals(const Topology& topology, const FaceGeometry& geometry) {
  const auto nv = static_cast<long>(topology.vertex_faces.rows());
  std::vector<Vec3> normals(nv, Vec3::Zero());
#pragma omp parallel for schedule(static)
  for (long v = 0; v < nv; ++v) normals[v] = vertex_normal(topology, geometry, static_cast<std::size_t>(v));
  return normals;
}

Vec3 vertex_normal(const Topology& topology, const FaceGeometry& geometry, std::size_t v) {
  Vec3 n = Vec3::Zero();
  for (const int* f = topology.vertex_faces.begin(v); f != topology.vertex_faces.end(v); ++f)
    n += geometry.areas[*f] * geometry.normals[*f];
  const double len = n.norm();
  return len > 0.0 ? Vec3(n / len) : Vec3::Zero();
}

double bbox_diagonal(const std::vector<Vec3>& positions) {
  if (positions.size() < 2) return 0.0;
  Vec3 lo = positions[0], hi = positions[0];
  for (const auto& p : positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

std::vector<int> distinct_triangles(const Mesh& mesh) {
  const std::size_t nf = mesh.num_faces();
  std::vector<Vec3> centroids(nf);
  for (std::size_t f = 0; f < nf; ++f) centroids[f] = face_centroid(mesh.positions, mesh.faces[f]);
  const std::vector<std::uint32_t> first = first_copies(centroids);  // copies share a centroid
  std::vector<int> kept;
  kept.reserve(nf);
  if (first.empty()) {
    for (std::size_t f = 0; f < nf; ++f) kept.push_back(static_cast<int>(f));
    return kept;
  }
  // Each centroid's faces (ascending) by their sorted corners.
  const CopyGroups groups = group_copies(first);
  using Key = std::array<double, 9>;
  auto key_of = [&](int f) {
    std::array<Vec3, 3> c{};
    for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(k)] = mesh.positions[mesh.faces[static_cast<std::size_t>(f)][k]] + Vec3::Zero();  // -0 as +0
    std::sort(c.begin(), c.end(), [](const Vec3& a, const Vec3& b) { return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3); });
    Key key{};
    for (std::size_t k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) key[3 * k + static_cast<std::size_t>(d)] = c[k][d];
    return key;
  };
  std::vector<std::uint8_t> keep(nf, 1);
  std::vector<std::pair<Key, int>> group;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (groups.count(g) < 2) continue;
    group.clear();
    for (int k = groups.start[g]; k < groups.start[g + 1]; ++k) {
      const int f = groups.members[static_cast<std::size_t>(k)];
      group.emplace_back(key_of(f), f);
    }
    std::sort(group.begin(), group.end());
    for (std::size_t k = 1; k < group.size(); ++k)
      if (group[k].first == group[k - 1].first) keep[static_cast<std::size_t>(group[k].second)] = 0;  // not the lowest index
  }
  for (std::size_t f = 0; f < nf; ++f)
    if (keep[f]) kept.push_back(static_cast<int>(f));
  return kept;
}

}  // namespace scanmesh
