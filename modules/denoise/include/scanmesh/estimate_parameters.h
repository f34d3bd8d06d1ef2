#pragma once
// `--auto`: denoising parameters chosen from the mesh itself, for users without ground truth.
#include <string>

#include "scanmesh/denoise.h"
#include "scanmesh/mesh.h"

namespace scanmesh {

/// What the estimator saw and what it chose.
struct AutoParameters {
  double noise_level = 0.0;       ///< estimated noise standard deviation / mean edge length
  double feature_fraction = 0.0;  ///< share of faces next to a sharp edge (dihedral > 35 deg after pre-smoothing)
  DenoiseOptions options;         ///< the input options with sigma_s, lambda and iterations replaced
};

/// Estimated noise standard deviation relative to the mean edge length: the median distance of a vertex
/// to the least-squares plane of its one-ring neighbours, scaled to a standard deviation.
double estimate_noise_level(const Mesh& mesh);

/// Share of faces next to an edge with a dihedral angle above 35 degrees, after light pre-smoothing.
double feature_fraction(const Mesh& mesh);

/// Chooses sigma_s, lambda_I and the iteration count for `mesh`; other fields come from `base`.
AutoParameters estimate_parameters(const Mesh& mesh, const DenoiseOptions& base = {});

}  // namespace scanmesh
