#pragma once
// What a mesh's noise looks like, measured from the mesh alone (for --auto and for warnings): a vertex's
// height over the plane of its one-ring varies slowly with curvature but jumps from vertex to vertex with
// noise, so the spread of those jumps measures the noise.
#include <vector>

#include "scanmesh/geometry.h"
#include "scanmesh/mesh.h"
#include "scanmesh/topology.h"

namespace scanmesh {

struct NoiseAnalysis {
  double mean_edge = 0.0;
  double median_jump = 0.0;        ///< mesh units
  double rms_jump = 0.0;           ///< mesh units; sensitive to outliers and sharp features
  double trimmed_rms_jump = 0.0;   ///< RMS of the lower 98% of the jumps (mesh units)
  /// Noise standard deviation relative to the mean edge length, from the median jump, calibrated on the
  /// noisy meshes of the standard pairs (read at 0.77-1.18x their stated level). The jumps see only the
  /// part of the noise along the normals: on the tuning corpus (`scanmesh noise`, level L) noise along the
  /// normals reads 1.02-1.32 L, noise in random directions 0.52-0.68 L (0.55-1.02 L at L = 0.1, where
  /// the shape's own jumps count).
  double level = 0.0;
  /// Share of interior vertices whose jump exceeds 6x the median while no neighbour's does: isolated
  /// outliers, the signature of impulsive noise (Gaussian noise and sharp features leave almost none).
  double isolated_outlier_share = 0.0;
  /// Share of vertices whose faces all have the same normal (to 1e-4): large for CAD tessellations and
  /// noise-free meshes, zero for anything carrying scanner noise.
  double exact_plane_fraction = 0.0;
  /// height_agreement(): near 1 where neighbouring vertices' heights over their one-rings agree (a surface
  /// smooth at the scale of its edges), near or below 0 where noise makes them unrelated.
  double height_agreement = 0.0;
};

/// Measures `mesh` (whose topology and face geometry are given).
NoiseAnalysis analyse_noise(const Mesh& mesh, const Topology& topology, const FaceGeometry& geometry);
NoiseAnalysis analyse_noise(const Mesh& mesh);

/// NoiseAnalysis::exact_plane_fraction alone (cheap: one pass over the vertices' faces).
double exact_plane_fraction(const Mesh& mesh, const Topology& topology, const FaceGeometry& geometry);

/// How far neighbouring vertices agree on their signed heights h over the mean of their one-rings (along
/// the vertex normal): the slope of the regression of a vertex's neighbours' mean h on its own h, both
/// taken about the mesh's mean h (interior vertices). Curvature gives neighbours alike heights (a smooth
/// sphere: near 1); independent noise gives each vertex its own and pushes its neighbours' the other way
/// (white noise on a plane: about -0.24). Deterministic (summed in vertex order).
double height_agreement(const Mesh& mesh, const Topology& topology, const FaceGeometry& geometry);

/// Per vertex: |height over the one-ring plane - neighbours' mean height| (mesh units); -1 where undefined
/// (boundary, fewer than three neighbours, no normal). Vertices flagged in `excluded` count neither in
/// their neighbours' one-ring planes nor in their mean heights.
std::vector<double> vertex_jumps(const Mesh& mesh, const Topology& topology, const FaceGeometry& geometry,
                                 const std::vector<std::uint8_t>* excluded = nullptr);

/// Impulsive noise: 1 for the vertices taken as outliers, those whose jump (`jump`, vertex_jumps() of
/// the same mesh) exceeds `limit_factor` x the median jump. With `peaks`, only those whose jump is also
/// the largest in their one-ring count, and then (once) those that are the largest when the first are
/// left out of their neighbours' rings: one displaced vertex raises its neighbours' jumps to about a
/// third of its own, while a coarse model's feature vertices come in chains of similar jumps, so a plain
/// limit takes both for outliers. Boundary vertices have no jump and are never outliers here
/// (boundary_curves.h: boundary_outliers).
std::vector<std::uint8_t> outlier_vertices(const Mesh& mesh, const Topology& topology, const FaceGeometry& geometry,
                                           const std::vector<double>& jump, double limit_factor, bool peaks);

}  // namespace scanmesh
