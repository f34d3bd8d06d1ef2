#pragma once
// `--auto`: denoising parameters chosen from the mesh itself, for users without ground truth.
#include <string>
#include <vector>

#include "scanmesh/denoise.h"
#include "scanmesh/geometry.h"
#include "scanmesh/topology.h"
#include "scanmesh/mesh.h"

namespace scanmesh {

/// What the estimator saw and what it chose.
struct AutoParameters {
  double noise_level = 0.0;       ///< estimated noise standard deviation / mean edge length
  double feature_fraction = 0.0;  ///< share of faces next to a sharp edge (dihedral > 35 deg after pre-smoothing)
  double exact_plane_fraction = 0.0;  ///< share of vertices whose faces all have the same normal (to 1e-4)
  DenoiseOptions options;         ///< the input options with sigma_s, lambda and iterations replaced
};

/// Estimated noise standard deviation relative to the mean edge length: the median distance of a vertex
/// to the least-squares plane of its one-ring neighbours, scaled to a standard deviation.
double estimate_noise_level(const Mesh& mesh);

/// The statistic behind estimate_noise_level, per interior vertex (mesh units): how far the vertex's height
/// over its one-ring plane differs from its neighbours' mean height.
std::vector<double> noise_jumps(const Mesh& mesh);
/// The same per vertex (-1 where undefined: boundary, fewer than three neighbours).
std::vector<double> vertex_jumps(const Mesh& mesh, const Topology& topology, const FaceGeometry& geometry);

/// Share of vertices whose faces all have the same normal (to 1e-4): large for CAD tessellations and
/// already clean meshes, zero for anything carrying scanner noise.
double exact_plane_fraction(const Mesh& mesh);

/// Share of faces next to an edge with a dihedral angle above 35 degrees, after light pre-smoothing.
double feature_fraction(const Mesh& mesh);

/// Chooses sigma_s, lambda_I, the iteration count and (for sharp-featured meshes) the neighbourhood radius
/// factor for `mesh`; other fields come from `base`.
/// A mesh that is evidently noise-free (exact_plane_fraction >= 0.1) gets 0 iterations.
AutoParameters estimate_parameters(const Mesh& mesh, const DenoiseOptions& base = {});

}  // namespace scanmesh
