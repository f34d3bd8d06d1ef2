#include "scanmesh/vertex_update.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "scanmesh/geometry.h"

namespace scanmesh {
namespace {

// True if `keep` holds every edge between two distinct vertices.
bool every_edge_kept(const Topology& topology, const std::vector<std::uint8_t>& keep) {
  for (std::size_t e = 0; e < topology.edges.size(); ++e)
    if (!keep[e] && topology.edges[e][0] != topology.edges[e][1]) return false;
  return true;
}

// How the filtered normals around a vertex meet, from their area-weighted tensor: one large eigenvalue on
// smooth parts, two along a sharp edge (then `edge` is its direction), three at a corner.
enum class Feature { smooth, edge, corner };
constexpr double kFeature = 0.1;  // eigenvalue (share of the area) above which a normal direction counts

// The sliver guard's step: the share of its tangential fidelity move a sliver's vertex takes per iteration.
// Large enough to undo the edge-normal term's pull within a few iterations; at 1 the moves overshoot and
// oscillate.
constexpr double kSliverStep = 0.3;

Feature classify(const Eigen::Matrix3d& tensor, double area, const Vec3& vertex_normal, double nlen, Vec3& edge) {
  if (!(area > 0.0)) return Feature::smooth;
  const Eigen::Matrix3d t = tensor / area;
  // The middle eigenvalue is at most trace - largest, and the largest at least the Rayleigh quotient of
  // the vertex normal, so where trace - quotient is clearly below kFeature (smooth parts, most vertices)
  // no eigenvalues are needed. The margin covers the solver's rounding: the result is as with the solve.
  if (nlen > 0.0 && t.trace() - vertex_normal.dot(t * vertex_normal) < kFeature - 1e-9) return Feature::smooth;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(t);
  const Vec3 ev = es.eigenvalues();  // ascending
  if (ev[0] >= kFeature) return Feature::corner;
  if (ev[1] >= kFeature) {
    edge = es.eigenvectors().col(0);
    return Feature::edge;
  }
  return Feature::smooth;
}

}  // namespace

Adjacency fidelity_neighbours(const Mesh& mesh, Topology& topology) {
  std::vector<std::uint8_t> solid(mesh.num_faces(), 0);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const Vec3& a = mesh.positions[mesh.faces[f][0]];
    const Vec3& b = mesh.positions[mesh.faces[f][1]];
    const Vec3& c = mesh.positions[mesh.faces[f][2]];
    const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    solid[f] = (b - a).cross(c - a).norm() > 1e-12 * longest2 ? 1 : 0;
  }
  const std::size_t nv = mesh.num_vertices();
  std::vector<std::uint8_t> keep(topology.edges.size(), 0);
  std::vector<int> count(nv + 1, 0);
  for (std::size_t e = 0; e < topology.edges.size(); ++e) {
    const auto [a, b] = topology.edges[e];
    if (a == b) continue;
    for (const int* f = topology.edge_faces.begin(e); f != topology.edge_faces.end(e) && !keep[e]; ++f) keep[e] = solid[*f];
    if (keep[e]) ++count[a + 1], ++count[b + 1];
  }
  // Usually every edge qualifies and the rows are topology.vertex_vertices exactly (built from the same
  // unique edges, self-loops skipped, ascending): take them instead of a second table of the same size.
  if (every_edge_kept(topology, keep)) {
    Adjacency n = std::move(topology.vertex_vertices);
    topology.vertex_vertices = Adjacency{};
    return n;
  }
  Adjacency n;
  for (std::size_t v = 0; v < nv; ++v) count[v + 1] += count[v];
  n.offsets.assign(count.begin(), count.end());
  n.indices.resize(static_cast<std::size_t>(n.offsets.back()));
  std::vector<int> fill(n.offsets.begin(), n.offsets.end() - 1);
  // Edges are sorted by (smaller, larger), so rows come out ascending when filled in two sweeps.
  for (std::size_t e = 0; e < topology.edges.size(); ++e)
    if (keep[e]) n.indices[fill[topology.edges[e][1]]++] = topology.edges[e][0];
  for (std::size_t e = 0; e < topology.edges.size(); ++e)
    if (keep[e]) n.indices[fill[topology.edges[e][0]]++] = topology.edges[e][1];
  return n;
}

void update_vertices(const std::vector<Vec3>& positions, const Topology& topology, const PackedRows& neighbours,
                     const FaceGeometry& geometry, const std::vector<Vec3>& filtered_normals, const VertexUpdateTerms& terms,
                     std::vector<Vec3>& updated, const std::vector<Face>* faces) {
  const auto nv = static_cast<long>(positions.size());
  updated.resize(positions.size());
  const bool stored = !geometry.centroids.empty();
  if (!stored && faces == nullptr && nv > 0)
    throw std::logic_error("update_vertices: geometry without centroids and no faces to compute them from");
  const bool guard = terms.slivers != nullptr;
  if (guard && terms.slivers->size() != geometry.areas.size())
    throw std::logic_error("update_vertices: one sliver flag per face needed");
  const double lambda = terms.lambda;
  const BoundaryCurves* boundary = terms.boundary;
  const bool feature_aware = terms.feature_aware;
  // The area-weighted tensor of the filtered normals around vertex i (for classify()).
  auto normal_tensor = [&](long i, double& area) {
    Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
    area = 0.0;
    for (const int* f = topology.vertex_faces.begin(i); f != topology.vertex_faces.end(i); ++f) {
      const Vec3& n = filtered_normals[*f];
      tensor += geometry.areas[*f] * n * n.transpose();
      area += geometry.areas[*f];
    }
    return tensor;
  };
  auto touches_sliver = [&](long i) {
    for (const int* f = topology.vertex_faces.begin(i); f != topology.vertex_faces.end(i); ++f)
      if ((*terms.slivers)[*f]) return true;
    return false;
  };
  // The tables as plain pointers: read through the captured vectors, every face in the loops below cost
  // three dependent loads just to find the arrays again (the stores to `updated` might have changed them,
  // as far as the compiler could tell).
  const Vec3* const pos = positions.data();
  const Face* const face = faces != nullptr ? faces->data() : nullptr;
  const Vec3* const centroids = stored ? geometry.centroids.data() : nullptr;
  const Vec3* const normal = filtered_normals.data();
  const double* const face_area = geometry.areas.data();
  const int* const vf_offsets = topology.vertex_faces.offsets.data();
  const int* const vf = topology.vertex_faces.indices.data();
  Vec3* const out = updated.data();
  auto centroid = [centroids, face, pos](int f) -> Vec3 {
    if (centroids != nullptr) return centroids[f];
    const Face& t = face[f];
    return (pos[t[0]] + pos[t[1]] + pos[t[2]]) / 3.0;  // face_centroid's bits
  };
#pragma omp parallel for schedule(static)
  for (long i = 0; i < nv; ++i) {
    const Vec3& vi = pos[i];
    const int* const f_begin = vf + vf_offsets[i];
    const int* const f_end = vf + vf_offsets[i + 1];
    const auto nfaces = static_cast<int>(f_end - f_begin);
    if (nfaces == 0) {  // isolated vertex: nothing to fit
      out[i] = vi;
      continue;
    }
    // Edge-normal orthogonality: move towards the planes of the filtered normals through the centroids.
    Vec3 fit = Vec3::Zero();
    Vec3 vertex_normal = Vec3::Zero();
    for (const int* f = f_begin; f != f_end; ++f) {
      const Vec3& n = normal[*f];
      fit += n * n.dot(centroid(*f) - vi);
      vertex_normal += face_area[*f] * n;
    }
    fit /= static_cast<double>(nfaces);
    const double nlen = vertex_normal.norm();
    if (nlen > 0.0) vertex_normal /= nlen;

    const bool on_boundary = boundary != nullptr && topology.boundary_vertex[i] != 0 && !boundary->ragged[i];
    if (on_boundary && boundary->corner[i]) {
      // A corner of the boundary curve (or an irregular boundary vertex) has too few curve neighbours to
      // fit a curve: it follows its faces' filtered normals only.
      out[i] = vi + fit;
      continue;
    }
    if (on_boundary) {
      // A boundary vertex sees faces on one side only: fitting it to their filtered normals (tilted
      // towards the interior on curved surfaces) makes the boundary flare out, and its half-sized
      // neighbourhood leaves it noisy. It is denoised as a point of its boundary curve instead
      // (smooth_boundary_curves); here it only evens out its edges along the curve.
      Vec3 r = Vec3::Zero();
      const int p = boundary->prev[i], q = boundary->next[i];
      if (p >= 0 && q >= 0) {
        const double wp = (positions[p] - vi).squaredNorm();
        const double wq = (positions[q] - vi).squaredNorm();
        const Vec3 t = positions[q] - positions[p];
        const double tlen = t.norm();
        if (wp + wq > 0.0 && tlen > 0.0) {
          const Vec3 d = (wp * positions[p] + wq * positions[q]) / (wp + wq) - vi;
          const Vec3 tu = t / tlen;
          r = 2.0 * d.dot(tu) * tu;
        }
      }
      out[i] = vi + lambda * r;
      continue;
    }
    // D_i with w_ij = |v_i - v_j|^2, then R_i = D_i + tangential part of D_i.
    Vec3 r = Vec3::Zero();
    Vec3 wsum = Vec3::Zero();
    double w = 0.0;
    neighbours.for_each(static_cast<std::size_t>(i), static_cast<int>(i), [&](int j) {
      const double wij = (pos[j] - vi).squaredNorm();
      wsum += wij * pos[j];
      w += wij;
    });
    const Vec3 d = w > 0.0 ? Vec3(wsum / w - vi) : Vec3::Zero();
    // Feature-aware moves: on sharp edges only along the edge, at corners none, so evening out triangles
    // does not round features. Classified only where needed (the eigenvalues are not free).
    const bool sliver = guard && w > 0.0 && touches_sliver(i);
    Feature feature = Feature::smooth;
    Vec3 edge = Vec3::Zero();
    if (w > 0.0 && (feature_aware || sliver)) {
      double area = 0.0;
      const Eigen::Matrix3d tensor = normal_tensor(i, area);
      feature = classify(tensor, area, vertex_normal, nlen, edge);
    }
    if (w > 0.0) {
      r = d + (d - d.dot(vertex_normal) * vertex_normal);
      if (feature_aware && feature == Feature::corner) r.setZero();
      if (feature_aware && feature == Feature::edge) r = 2.0 * d.dot(edge) * edge;
    }
    out[i] = vi + fit + lambda * r;
    if (sliver) {
      // The sliver guard: the edge-normal term pulls vertices near a sharp edge onto it, and once lambda
      // has decayed nothing spreads them again, so triangles there collapse into slivers and fold. A
      // vertex of a sliver takes a fixed share of its tangential fidelity move every iteration, within the
      // surface (along the edge on a sharp edge, none at a corner), so the surface keeps its shape.
      Vec3 t = d - d.dot(vertex_normal) * vertex_normal;
      if (feature == Feature::corner) t.setZero();
      if (feature == Feature::edge) t = d.dot(edge) * edge;
      out[i] += kSliverStep * t;
    }
  }
}

std::size_t mark_new_slivers(const std::vector<Vec3>& positions, const std::vector<Vec3>& input, const std::vector<Face>& faces,
                             double limit, std::vector<std::uint8_t>& flags) {
  flags.resize(faces.size());
  std::size_t count = 0;
  const auto nf = static_cast<long>(faces.size());
#pragma omp parallel for schedule(static) reduction(+ : count)
  for (long f = 0; f < nf; ++f) {
    const Face& t = faces[f];
    // The root-free test first; the shapes themselves only for the few it flags.
    const bool sliver = TriangleTerms(positions[t[0]], positions[t[1]], positions[t[2]]).sliver(limit) &&
                        triangle_shape(positions[t[0]], positions[t[1]], positions[t[2]]) > triangle_shape(input[t[0]], input[t[1]], input[t[2]]);
    flags[f] = sliver ? 1 : 0;
    count += sliver ? 1 : 0;
  }
  return count;
}

}  // namespace scanmesh
