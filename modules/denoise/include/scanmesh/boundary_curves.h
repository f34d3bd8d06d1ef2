#pragma once
// Open boundaries kept in place (beyond the paper): each boundary loop is denoised as a curve, by a local
// quadratic fit along its arc length that reproduces lines and circles and never reaches across a corner,
// instead of fitting boundary vertices to the faces on one side of them (which makes boundaries flare
// out and creep inwards). Loops too ragged to be curves (a depth camera's pixel staircase) are treated
// like the interior, as in the paper.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "scanmesh/mesh.h"
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
};

/// Windows along a boundary loop (the curve fit) reach at most this many edges
/// each way. A uniform loop needs ~3 x boundary_window (<= 30); a loop of many tiny edges and a few long
/// ones (whose mean edge, hence window, spans thousands of tiny edges) would otherwise cost O(n^2).
inline constexpr int kBoundaryWindowMaxEdges = 64;

/// Finds the loops, their corners (turn above 50 degrees over three-edge chords; loops under 8 vertices
/// are polygons, all corners) and ragged loops (mean turn above 70 degrees).
BoundaryCurves build_boundary_curves(const Mesh& mesh, const Topology& topology);

/// Keeps repeated smoothing from wearing a boundary away. The fit reproduces lines and circles, but a
/// curve with detail at the window's scale (a relief's outline) moves a little with every pass, and a
/// hundred passes carry it off the surface. A loop stops moving once the RMS of its fitted vertices' moves
/// across the curve, counted from their input positions, would pass `max_rms` (the noise across a curve,
/// i.e. at most sqrt 2 x the noise along the normals); the pass that would take it there is not applied.
struct BoundaryDrift {
  const std::vector<Vec3>* input = nullptr;  ///< the positions before the first pass
  double max_rms = std::numeric_limits<double>::infinity();
  std::vector<std::uint8_t> stopped;  ///< per loop: 1 once it has stopped (filled by smooth_boundary_curves)
};

/// Smooths each boundary loop as a curve: a robust local quadratic fit over arc length (window = Gaussian
/// width in mean boundary edge lengths, at most kBoundaryWindowMaxEdges each way) that reproduces lines
/// and circles, so the boundary does not shrink, and does not smooth across corners (which stay for
/// update_vertices). Each vertex moves across the curve only (towards the fit, less its part along the
/// chord of its two curve neighbours): spacing along the curve is update_vertices' job. With `along_too`
/// (impulsive noise: the vertices that move are off by impulses, not by noise) moves are taken whole. A
/// move that would turn one of the vertex's triangles by more than 45 degrees or make
/// its shape (circumradius / shortest edge) worse than 1.5 is halved, up to three times, then dropped:
/// straightening a jagged scan boundary must not flatten the triangles behind it. With `drift`, loops
/// stop as described there.
void smooth_boundary_curves(std::vector<Vec3>& positions, const std::vector<Face>& faces, const Topology& topology,
                            const BoundaryCurves& curves, double window, bool along_too = false, BoundaryDrift* drift = nullptr);

/// Impulsive noise along the boundary: 1 for boundary vertices displaced off their curve, judged as the
/// interior's outliers are (noise_analysis.h, outlier_vertices with peaks) but in one dimension: the
/// jump of the curve's second difference |L_v - (L_prev + L_next) / 2|, L_v = p_v - (p_prev + p_next) / 2,
/// above `limit_factor` x its median over the boundary and the larger of the two neighbours'. Corners and
/// vertices without two curve neighbours on each side are never outliers.
std::vector<std::uint8_t> boundary_outliers(const std::vector<Vec3>& positions, const BoundaryCurves& curves, double limit_factor);

}  // namespace scanmesh
