#pragma once
// Stage 2 of the robust two-stage denoiser: one gradient step of the vertex update (Yadav et al. 2019,
// eq. 4-6, with the typos fixed as in docs):
//   v_i <- v_i + 1/|F_v(i)| sum_k n~_k (n~_k . (c_k - v_i)) + lambda_I (D_i + D_t_i)
// where D_i is the |v_i - v_j|^2-weighted differential coordinate and D_t_i its tangential part.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "scanmesh/boundary_curves.h"
#include "scanmesh/denoise.h"
#include "scanmesh/geometry.h"
#include "scanmesh/packed_rows.h"
#include "scanmesh/topology.h"

namespace scanmesh {

/// The neighbours each vertex's fidelity term R_i averages over: vertex_vertices, but only through edges
/// of at least one non-degenerate face (area above 1e-12 x longest edge^2). A zero-area sliver joining two
/// far vertices would otherwise pull both across the object (the weights grow with |v_i - v_j|^2).
/// When every edge qualifies (most meshes) the result is topology.vertex_vertices itself, moved out rather
/// than copied (topology.vertex_vertices is then left with no rows).
Adjacency fidelity_neighbours(const Mesh& mesh, Topology& topology);

/// The terms of one vertex-update step besides the edge-normal fit.
struct VertexUpdateTerms {
  double lambda = 0.0;  ///< weight of the isotropic fidelity term R_i
  /// Non-null: boundary vertices only even out their edges along the boundary (their denoising is
  /// smooth_boundary_curves's job).
  const BoundaryCurves* boundary = nullptr;
  /// R_i acts only along sharp edges (not across them) and not at corners, judged from the normal tensor
  /// of the filtered normals around the vertex.
  bool feature_aware = false;
  /// Sliver guard: per face, 1 where the run has made a sliver (mark_new_slivers); null = off. Vertices of
  /// those faces also move by 0.3 x the tangential part of D_i, feature-aware as above, whatever lambda is.
  const std::vector<std::uint8_t>* slivers = nullptr;
};

/// Triangle (p, q, r) in scalars: its squared edge lengths (a2 opposite p, b2 opposite q, c2 opposite r) and
/// the cross product (q - p) x (r - p), with the operations Eigen's cross() and squaredNorm() do (the same
/// bits). Eigen's two-lane code for the cross product stored two halves and loaded them as one, which
/// stalled the store forwarding on every face (a third of the sliver pass).
struct TriangleTerms {
  double a2, b2, c2, cx, cy, cz;
  TriangleTerms(const Vec3& p, const Vec3& q, const Vec3& r) {
    const double ux = q.x() - p.x(), uy = q.y() - p.y(), uz = q.z() - p.z();  // q - p
    const double vx = r.x() - p.x(), vy = r.y() - p.y(), vz = r.z() - p.z();  // r - p
    const double wx = r.x() - q.x(), wy = r.y() - q.y(), wz = r.z() - q.z();  // r - q
    a2 = wx * wx + wy * wy + wz * wz, b2 = vx * vx + vy * vy + vz * vz, c2 = ux * ux + uy * uy + uz * uz;
    cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
  }
  [[nodiscard]] double cross2() const { return cx * cx + cy * cy + cz * cz; }
  /// True if the circumradius exceeds `limit` x the shortest edge (or there is no area), without roots:
  /// R = abc / (4A), so R > limit x l_min <=> a^2 b^2 c^2 > limit^2 l_min^2 16 A^2, and 16 A^2 = 4 |cross|^2.
  [[nodiscard]] bool sliver(double limit) const { return a2 * b2 * c2 > 4.0 * limit * limit * std::min({a2, b2, c2}) * cross2(); }
};

/// Flags the faces whose circumradius exceeds `limit` x their shortest edge and that are worse shaped than
/// they were in `input` (the run made them slivers; a tessellation's own slivers are left as they are).
/// Returns how many.
std::size_t mark_new_slivers(const std::vector<Vec3>& positions, const std::vector<Vec3>& input, const std::vector<Face>& faces,
                             double limit, std::vector<std::uint8_t>& flags);

/// One vertex-update step from `positions` into `updated`; R_i averages over `neighbours`
/// (fidelity_neighbours, packed with each row anchored at its vertex). If `geometry` has no centroids,
/// each face's is computed from `positions` and `faces`.
void update_vertices(const std::vector<Vec3>& positions, const Topology& topology, const PackedRows& neighbours,
                     const FaceGeometry& geometry, const std::vector<Vec3>& filtered_normals, const VertexUpdateTerms& terms,
                     std::vector<Vec3>& updated, const std::vector<Face>* faces = nullptr);

}  // namespace scanmesh
