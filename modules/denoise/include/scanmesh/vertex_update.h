#pragma once
// Stage 2 of the robust two-stage denoiser: one gradient step of the vertex update (Yadav et al. 2019,
// eq. 4-6, with the typos fixed as in docs):
//   v_i <- v_i + 1/|F_v(i)| sum_k n~_k (n~_k . (c_k - v_i)) + lambda_I (D_i + D_t_i)
// where D_i is the |v_i - v_j|^2-weighted differential coordinate and D_t_i its tangential part.
#include <vector>

#include "scanmesh/denoise.h"
#include "scanmesh/geometry.h"
#include "scanmesh/topology.h"

namespace scanmesh {

/// Boundary curves in the form the vertex update needs: loop edges in order, and per boundary vertex
/// its two neighbours along the boundary (or -1).
struct BoundaryCurves {
  struct Edge {
    int a, b;  ///< a -> b follows the orientation of `face`
    int face;
  };
  std::vector<Edge> edges;
  Adjacency loop_edges;                   ///< edge indices of each loop, in order
  std::vector<std::uint8_t> loop_closed;  ///< per loop
  std::vector<int> prev, next;            ///< per vertex: boundary neighbours (-1 if none/irregular)
  std::vector<std::array<int, 2>> vertex_edges;  ///< per vertex: incident loop edges (-1 if none)
  std::vector<std::uint8_t> corner;  ///< per vertex: 1 where the input boundary turns by > 50 deg, or is irregular
  /// Per vertex: 1 on loops so ragged (mean turn between consecutive edges > 70 deg, e.g. the pixel
  /// staircase of a depth-camera scan) that no curve describes them; such vertices are treated like
  /// interior ones, as in the paper.
  std::vector<std::uint8_t> ragged;
  std::vector<Vec3> normals;  ///< per edge: filtered in-surface outward normal (filter_boundary_normals)
};

BoundaryCurves build_boundary_curves(const Mesh& mesh, const Topology& topology);

/// Filters the in-surface outward normals m_e = normalize(edge x n~_face) of the boundary edges along
/// each loop with the same robust bilateral weights as stage 1 (closeness on midpoint distance with
/// sigma = mean boundary edge length, up to `radius_factor` of it).
void filter_boundary_normals(const std::vector<Vec3>& positions, BoundaryCurves& curves,
                             const std::vector<Vec3>& filtered_face_normals, double sigma_s,
                             RobustEstimator estimator, double radius_factor);

/// The neighbours each vertex's fidelity term R_i averages over: vertex_vertices, but only through edges
/// of at least one non-degenerate face (area above 1e-12 x longest edge^2). A zero-area sliver joining two
/// far vertices would otherwise pull both across the object (the weights grow with |v_i - v_j|^2).
Adjacency fidelity_neighbours(const Mesh& mesh, const Topology& topology);

/// One vertex-update step from `positions` into `updated`; R_i averages over `neighbours`
/// (fidelity_neighbours). With `boundary` non-null, boundary vertices
/// only even out their edges along the boundary (their denoising is smooth_boundary_curves's job).
/// With `feature_aware`, the fidelity term R_i acts only along sharp edges (not across them) and not at
/// corners, judged from the normal tensor of the filtered normals around the vertex.
void update_vertices(const std::vector<Vec3>& positions, const Topology& topology, const Adjacency& neighbours,
                     const FaceGeometry& geometry, const std::vector<Vec3>& filtered_normals, double lambda,
                     const BoundaryCurves* boundary, bool feature_aware, std::vector<Vec3>& updated);

/// Smooths each boundary loop as a curve: a robust local quadratic fit over arc length (window = Gaussian
/// width in mean boundary edge lengths) that reproduces lines and circles, so the boundary does not shrink,
/// and does not smooth across corners (which stay for update_vertices). A move that would turn one of
/// the vertex's triangles by more than 45 degrees or make its shape (circumradius / shortest edge) worse
/// than 1.5 is halved, up to three times, then dropped: straightening a jagged scan boundary must not
/// flatten the triangles behind it.
void smooth_boundary_curves(std::vector<Vec3>& positions, const std::vector<Face>& faces, const Topology& topology,
                            const BoundaryCurves& curves, double window);

}  // namespace scanmesh
