#include "scanmesh/vertex_update.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace scanmesh {
namespace {

// True if `keep` holds every edge between two distinct vertices.
bool every_edge_kept(const Topology& topology, const std::vector<std::uint8_t>& keep) {
  for (std::size_t e = 0; e < topology.edges.size(); ++e)
    if (!keep[e] && topology.edges[e][0] != topology.edges[e][1]) return false;
  return true;
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
                     const FaceGeometry& geometry, const std::vector<Vec3>& filtered_normals, double lambda,
                     const BoundaryCurves* boundary, bool feature_aware, std::vector<Vec3>& updated,
                     const std::vector<Face>* faces) {
  const auto nv = static_cast<long>(positions.size());
  updated.resize(positions.size());
  const bool stored = !geometry.centroids.empty();
  if (!stored && faces == nullptr && nv > 0)
    throw std::logic_error("update_vertices: geometry without centroids and no faces to compute them from");
  auto centroid = [&](int f) -> Vec3 { return stored ? geometry.centroids[f] : face_centroid(positions, (*faces)[f]); };
#pragma omp parallel for schedule(static)
  for (long i = 0; i < nv; ++i) {
    const Vec3& vi = positions[i];
    const int nfaces = topology.vertex_faces.size(i);
    if (nfaces == 0) {  // isolated vertex: nothing to fit
      updated[i] = vi;
      continue;
    }
    // Edge-normal orthogonality: move towards the planes of the filtered normals through the centroids.
    Vec3 fit = Vec3::Zero();
    Vec3 vertex_normal = Vec3::Zero();
    // The normal tensor (used below when feature_aware) in the same pass over the faces.
    Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
    double area = 0.0;
    for (const int* f = topology.vertex_faces.begin(i); f != topology.vertex_faces.end(i); ++f) {
      const Vec3& n = filtered_normals[*f];
      fit += n * n.dot(centroid(*f) - vi);
      vertex_normal += geometry.areas[*f] * n;
      if (feature_aware) {
        tensor += geometry.areas[*f] * n * n.transpose();
        area += geometry.areas[*f];
      }
    }
    fit /= static_cast<double>(nfaces);
    const double nlen = vertex_normal.norm();
    if (nlen > 0.0) vertex_normal /= nlen;

    const bool on_boundary = boundary != nullptr && topology.boundary_vertex[i] != 0 && !boundary->ragged[i];
    if (on_boundary && boundary->corner[i]) {
      // A corner of the boundary curve (or an irregular boundary vertex) has too few curve neighbours to
      // fit a curve: it follows its faces' filtered normals only.
      updated[i] = vi + fit;
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
      updated[i] = vi + lambda * r;
      continue;
    }
    // D_i with w_ij = |v_i - v_j|^2, then R_i = D_i + tangential part of D_i.
    Vec3 r = Vec3::Zero();
    Vec3 wsum = Vec3::Zero();
    double w = 0.0;
    neighbours.for_each(static_cast<std::size_t>(i), static_cast<int>(i), [&](int j) {
      const double wij = (positions[j] - vi).squaredNorm();
      wsum += wij * positions[j];
      w += wij;
    });
    if (w > 0.0) {
      const Vec3 d = wsum / w - vi;
      r = d + (d - d.dot(vertex_normal) * vertex_normal);
      if (feature_aware) {
        // Normal tensor of the filtered normals: one large eigenvalue on smooth parts, two along a
        // sharp edge, three at a corner. On edges only the move along the edge is kept, at corners none,
        // so the fidelity term evens out triangles without rounding features.
        constexpr double kFeature = 0.1;
        // The middle eigenvalue is at most trace - largest, and the largest at least the Rayleigh
        // quotient of the vertex normal, so where trace - quotient is clearly below kFeature (smooth
        // parts, most vertices) the eigenvalues cannot change r and are not computed. The margin covers
        // the solver's rounding, so the result is the same as with the solve.
        const Eigen::Matrix3d t = area > 0.0 ? Eigen::Matrix3d(tensor / area) : Eigen::Matrix3d::Zero();
        const bool smooth = area > 0.0 && nlen > 0.0 && t.trace() - vertex_normal.dot(t * vertex_normal) < kFeature - 1e-9;
        if (area > 0.0 && !smooth) {
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
          es.computeDirect(t);
          const Vec3 ev = es.eigenvalues();  // ascending
          if (ev[0] >= kFeature) {
            r.setZero();
          } else if (ev[1] >= kFeature) {
            const Vec3 t = es.eigenvectors().col(0);
            r = 2.0 * d.dot(t) * t;
          }
        }
      }
    }
    updated[i] = vi + fit + lambda * r;
  }
}

}  // namespace scanmesh
