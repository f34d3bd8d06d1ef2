#pragma once
// Robust two-stage mesh denoising: Yadav, Reitebuch, Polthier, "Robust and High Fidelity Mesh
// Denoising", IEEE TVCG 2019. Each iteration filters the face normals with a robust bilateral filter
// (stage 1, normal_filtering.h) and then moves the vertices to agree with the filtered normals plus an
// isotropic fidelity term lambda_I * R_i (stage 2, vertex_update.h); lambda_I decays every iteration.
#include <functional>
#include <string>
#include <vector>

#include "scanmesh/mesh.h"

namespace scanmesh {

/// Robust estimator whose weight function g(x, sigma_s) compares two unit normals, x = |n_i - n_j| in [0, 2].
enum class RobustEstimator {
  tukey,       ///< 0.5 (1 - (x/s)^2)^2 for x <= s, else 0: no diffusion across features (the paper's choice)
  gaussian,    ///< exp(-x^2 / (2 s^2)): classic bilateral normal filter, blurs strong features slightly
  huber,       ///< 1 for x <= s, else s/x: never fully stops diffusion
  lorentzian,  ///< 1 / (1 + x^2 / (2 s^2))
};

/// Which faces form the geometric neighbourhood Omega_i of face i.
enum class NeighbourhoodKind {
  ball,            ///< every face whose centroid lies within r of c_i (the paper)
  connected_ball,  ///< only those reachable from i through edge-adjacent faces inside the ball (the
                   ///< authors' code): thin walls and nearby sheets do not mix
};

/// Options of the denoiser; also the schema of the `mesh.denoise` pipeline stage.
struct DenoiseOptions {
  /// Similarity kernel width sigma_s on |n_i - n_j| (range 0.05 .. 2). Smaller keeps more features but
  /// leaves more noise; larger smooths more and rounds sharp edges. CAD-like 0.3-0.6, organic 0.6-1.0.
  double sigma_s = 0.7;
  /// Fidelity/isotropic weight lambda_I (range 0 .. 1). Evens out triangles and stops flips under strong
  /// noise; too large shrinks and blurs. Multiplied by `decay` after every iteration.
  double lambda = 0.2;
  /// Number of iterations p (>= 1). More removes more noise; too many over-smooth organic shapes.
  int iterations = 100;
  /// lambda_I <- decay * lambda_I after every iteration (the paper: 0.6; the authors' code: 0.7).
  double decay = 0.6;
  /// Neighbourhood radius r = radius_factor * c_a, where c_a is the mean distance between centroids of
  /// edge-adjacent faces; the closeness kernel width is sigma_c = c_a (the paper: 2).
  double radius_factor = 2.0;
  RobustEstimator estimator = RobustEstimator::tukey;
  NeighbourhoodKind neighbourhood = NeighbourhoodKind::ball;
  /// Recompute the neighbourhoods from the moved centroids every iteration (slower; rarely matters).
  bool recompute_neighbourhoods = false;
  /// Keep open boundaries in place: boundary vertices are denoised as points of their boundary curve
  /// (robust local quadratic fit along the curve, which keeps lines, circles and corners) instead of
  /// being fitted to one-sided face neighbourhoods. Off = the authors' behaviour, where open boundaries
  /// creep inwards.
  bool keep_boundary = true;
  /// With keep_boundary: width of the boundary curve fit, in mean boundary edge lengths (0.5 .. 10).
  double boundary_window = 2.0;
  /// Fidelity term R_i that does not round sharp edges and corners (beyond the paper): on a vertex
  /// whose filtered normals span two directions it moves only along the edge, at three none.
  bool feature_aware_fidelity = false;
  /// Two kernels (beyond the paper): faces whose neighbourhood bends by less than `feature_threshold`
  /// (max |m_i - m_j| of pre-filtered normals) use this wider sigma_s, the others `sigma_s`. 0 = off.
  double smooth_sigma_s = 0.0;
  double feature_threshold = 0.5;
  /// The pre-filter behind feature_threshold: passes of the normal filter with this sigma_s.
  double feature_prefilter_sigma = 2.0;
  int feature_prefilter_passes = 2;
  /// Each vertex moves along its normal by at most this multiple of its own noise jump (the largest in
  /// its one-ring), so vertices the noise left alone stay. 0 = off.
  double displacement_cap = 0.0;
  /// Impulsive noise: only vertices whose noise jump exceeds this multiple of the median jump move (the
  /// outliers); the others keep their positions. 0 = off (every vertex moves).
  double outlier_jump = 0.0;
};

/// What a denoising run did (for reports).
struct DenoiseReport {
  double mean_centroid_distance = 0.0;  ///< c_a of the input
  double mean_neighbourhood_size = 0.0;  ///< faces per Omega_i
  std::size_t capped_neighbourhoods = 0;  ///< faces with more than max_neighbourhood_size() neighbours (nearest used)
  std::size_t boundary_vertices = 0;
  int iterations = 0;
  double seconds_neighbourhoods = 0.0;
  double seconds_filtering = 0.0;
  double seconds_vertex_update = 0.0;
};

/// Called after every iteration with (iterations done, total).
using ProgressCallback = std::function<void(int, int)>;
/// Called after every iteration with the iterations done and the current vertex positions (benches record
/// quality curves with it; it must not keep the reference).
using IterationObserver = std::function<void(int, const std::vector<Vec3>&)>;

/// Parses/prints option values ("tukey", "connected_ball", ...). Parsing throws UsageError listing the choices.
RobustEstimator parse_estimator(const std::string& name);
NeighbourhoodKind parse_neighbourhood(const std::string& name);
std::string to_string(RobustEstimator estimator);
std::string to_string(NeighbourhoodKind kind);

/// Throws UsageError naming the option if a value is out of range.
void validate(const DenoiseOptions& options);

/// Denoises `mesh` in place. Connectivity, vertex order and vertex properties are kept; stored vertex
/// normals (nx, ny, nz) are recomputed from the result. Degenerate faces, isolated vertices, non-manifold
/// edges and several components are allowed. Deterministic: the result does not depend on the thread count.
/// \throw UsageError for invalid options.
DenoiseReport denoise(Mesh& mesh, const DenoiseOptions& options, const ProgressCallback& progress = {},
                      const IterationObserver& observer = {});

}  // namespace scanmesh
