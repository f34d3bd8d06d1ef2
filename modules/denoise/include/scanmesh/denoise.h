#pragma once
// Robust two-stage mesh denoising: Yadav, Reitebuch, Polthier, "Robust and High Fidelity Mesh
// Denoising", IEEE TVCG 2019. Each iteration filters the face normals with a robust bilateral filter
// (stage 1, normal_filtering.h) and then moves the vertices to agree with the filtered normals plus an
// isotropic fidelity term lambda_I * R_i (stage 2, vertex_update.h); lambda_I decays every iteration.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "scanmesh/mesh.h"
#include "scanmesh/schema.h"

namespace scanmesh {

struct Topology;
struct FaceGeometry;

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

/// Options of the denoiser; also the schema of the `mesh.denoise` pipeline stage (see schema() below for
/// each field's unit, range and meaning).
struct DenoiseOptions {
  double sigma_s = 0.7;
  double lambda = 0.2;
  int iterations = 100;
  bool automatic = false;
  double target_displacement = 0.0;
  double decay = 0.6;
  double radius_factor = 2.0;
  RobustEstimator estimator = RobustEstimator::tukey;
  NeighbourhoodKind neighbourhood = NeighbourhoodKind::ball;
  bool recompute_neighbourhoods = false;
  bool keep_boundary = true;
  double boundary_window = 2.0;
  bool feature_aware_fidelity = false;
  double sliver_guard = 3.0;
  double outlier_jump = 0.0;
  bool outlier_peaks = false;
  bool scanned = false;
  bool vertices_are_points = false;

  static const Schema<DenoiseOptions>& schema() {
    using O = DenoiseOptions;
    static const Schema<O> s =
        Schema<O>()
            .number("sigma_s", &O::sigma_s, open_closed(0, 2), "unitless",
                    "Width of the robust similarity kernel on |n_i - n_j| of two unit face normals: smaller keeps more "
                    "features and more noise, larger smooths more and rounds sharp edges (CAD 0.5-0.7, organic 1-2).")
            .number("lambda", &O::lambda, closed(0, 1), "unitless",
                    "Weight lambda_I of the isotropic fidelity term: evens out triangles and prevents flips under strong "
                    "noise; too large shrinks and blurs. Multiplied by decay after every iteration.")
            .integer("iterations", &O::iterations, closed(0, 100000), "count",
                     "Iterations (at most, with target_displacement): more removes more noise; too many flatten detail.")
            .flag("auto", &O::automatic,
                  "Choose sigma_s, lambda, iterations, the radius and the stopping point from the mesh itself "
                  "(noise level, sharp features, impulsive noise); values given explicitly still win.")
            .number("target_displacement", &O::target_displacement, closed(0, 100), "x mean edge",
                    "Stop once the vertices have moved this far from the input along their normals (RMS): the "
                    "discrepancy principle, about the noise's size; 0 runs every iteration.")
            .number("decay", &O::decay, closed(0, 1), "unitless", "lambda_I <- decay x lambda_I after every iteration (the paper: 0.6).")
            .number("radius_factor", &O::radius_factor, closed(0.5, 10), "x c_a",
                    "Neighbourhood radius in units of c_a, the mean distance between centroids of adjacent faces; "
                    "the closeness kernel width is c_a.")
            .choice("estimator", &O::estimator,
                    {{"tukey", RobustEstimator::tukey}, {"gaussian", RobustEstimator::gaussian},
                     {"huber", RobustEstimator::huber}, {"lorentzian", RobustEstimator::lorentzian}},
                    "Robust similarity weight: tukey stops diffusion across features completely, the others never fully.")
            .choice("neighbourhood", &O::neighbourhood,
                    {{"ball", NeighbourhoodKind::ball}, {"connected_ball", NeighbourhoodKind::connected_ball}},
                    "ball: every face within the radius; connected_ball: only faces reachable through adjacent faces "
                    "(thin walls and close sheets do not mix).")
            .flag("recompute_neighbourhoods", &O::recompute_neighbourhoods,
                  "Rebuild the neighbourhoods every iteration (slower, rarely different).")
            .flag("keep_boundary", &O::keep_boundary,
                  "Denoise open boundaries as curves so they stay in place (each loop moves at most as far as the "
                  "noise across it); false treats boundary vertices like interior ones, as the authors' code does "
                  "(boundaries creep inwards).")
            .number("boundary_window", &O::boundary_window, closed(0.5, 10), "x boundary edge",
                    "Width of the boundary-curve fit: wider smooths open boundaries more "
                    "(and starts to round them).")
            .flag("feature_aware_fidelity", &O::feature_aware_fidelity,
                  "Fidelity term that moves vertices only along sharp edges and not at corners (a clean CAD part stays "
                  "exact; measured worse on noisy fandisk).")
            .number("sliver_guard", &O::sliver_guard, closed(0, 100), "x shortest edge",
                    "Triangles the run has made worse than this (circumradius over shortest edge; 0.577 is equilateral) "
                    "and worse than they were get their vertices evened out within the surface in every iteration, "
                    "along sharp edges only and not at corners, so edges pulling vertices together cannot fold them "
                    "into slivers; 0 = off (the paper), otherwise at least 1.")
            .number("outlier_jump", &O::outlier_jump, closed(0, 1000), "x median jump",
                    "Impulsive noise: only vertices whose height jump over their one-ring exceeds this multiple of the "
                    "median move (the outliers), the rest stay (boundary vertices: judged the same way along their "
                    "boundary curve); 0 moves every vertex.")
            .flag("outlier_peaks", &O::outlier_peaks,
                  "With outlier_jump: of the vertices over the limit only those with the largest jump in their one-ring "
                  "move (then those largest once the first are left out): a coarse model's corners, which come in "
                  "chains, stay.")
            .flag("scanned", &O::scanned,
                  "The mesh was triangulated from scanned points, so every vertex carries the scanner's noise: auto does "
                  "not take isolated spikes for impulsive noise (a triangulation's slivers read as such, and moving only "
                  "them would leave the rest noisy), and its last step also undoes folds on the triangulation's own "
                  "slivers. The main job sets it for the meshes it makes.")
            .flag("vertices_are_points", &O::vertices_are_points,
                  "The mesh's vertices are the scanned points themselves (greedy projection, organized meshing), not a "
                  "surface fitted to them (Poisson): auto lowers the wide kernel's fidelity weight lambda under weak "
                  "noise, where evening out such an irregular triangulation moves its vertices off the surface more "
                  "than the noise had, and where no feature-keeping iteration passes its result check it tries the "
                  "wide kernel instead of returning the input. The main job sets it when its mesh keeps the points.");
    return s;
  }
};

/// What a denoising run did (for reports).
struct DenoiseReport {
  double mean_centroid_distance = 0.0;  ///< c_a of the input
  double mean_neighbourhood_size = 0.0;  ///< faces per Omega_i
  std::size_t capped_neighbourhoods = 0;  ///< faces with more than max_neighbourhood_size() neighbours (nearest used)
  std::size_t boundary_vertices = 0;
  std::size_t boundary_loops = 0;  ///< loops denoised as curves (keep_boundary)
  /// ...of which stopped moving because they had moved as far as the noise across them (BoundaryDrift in
  /// boundary_curves.h): a relief's outline, which the curve fit would otherwise carry off the surface.
  std::size_t boundary_loops_stopped = 0;
  int iterations = 0;
  double seconds_neighbourhoods = 0.0;
  double seconds_filtering = 0.0;
  double seconds_vertex_update = 0.0;
  /// Why the run ended: "iterations", "target displacement", "observer" or "nothing to do".
  std::string stop_reason = "nothing to do";
  double displacement = 0.0;  ///< RMS normal displacement from the input at the end (mesh units)
  /// Share of the input's vertices lying exactly in the plane of their faces (noise_analysis.h): a
  /// noise-free tessellation, which denoising can only disturb.
  double exact_plane_fraction = 0.0;
};

/// Called after every iteration with (iterations done, total).
using ProgressCallback = std::function<void(int, int)>;
/// Called after every iteration with the iterations done and the current vertex positions; returning
/// false stops the run there (--auto decides with it; benches record quality curves). It must not keep
/// the reference. During the run the mesh given to denoise() keeps its faces but not its positions
/// (they are set aside, so a large mesh is not held twice): the observer reads them from its argument.
using IterationObserver = std::function<bool(int, const std::vector<Vec3>&)>;

/// Parses/prints option values ("tukey", "connected_ball", ...). Parsing throws UsageError listing the choices.
RobustEstimator parse_estimator(const std::string& name);
NeighbourhoodKind parse_neighbourhood(const std::string& name);
std::string to_string(RobustEstimator estimator);
std::string to_string(NeighbourhoodKind kind);

/// Throws UsageError naming the option if a value is out of range.
void validate(const DenoiseOptions& options);

/// Set-up that several runs of the denoiser on one input share (--auto filters the input for its result
/// check and then runs the denoiser on it up to twice, all with the same radius): the spatial order and
/// the input's ball neighbourhoods. It binds to the first mesh it is used with (a fingerprint of positions
/// and faces); runs on any other mesh, or with another radius or neighbourhood kind, compute their own.
/// Results are the same with or without it. Holds one neighbourhood table (~4 bytes per neighbour).
class DenoiseCache {
 public:
  DenoiseCache();
  ~DenoiseCache();
  DenoiseCache(const DenoiseCache&) = delete;
  DenoiseCache& operator=(const DenoiseCache&) = delete;
  /// Entries of the neighbourhood table it holds (0 before a run has filled it).
  [[nodiscard]] std::size_t cached_neighbours() const;
  /// With `keep`, a run copies the connectivity the cache holds instead of taking it, so a later run on
  /// the same mesh needs no second build (the copy costs about 80 bytes per face while both live).
  void keep_topology(bool keep) { keep_topology_ = keep; }
  [[nodiscard]] bool keeps_topology() const { return keep_topology_; }
  struct State;
  std::unique_ptr<State> state;

 private:
  bool keep_topology_ = false;
};

/// Denoises `mesh` in place. Connectivity, vertex order and vertex properties are kept; stored vertex
/// normals (nx, ny, nz) are recomputed from the result. Degenerate faces, isolated vertices, non-manifold
/// edges and several components are allowed. Deterministic: the result does not depend on the thread count.
/// \throw UsageError for invalid options.
/// With `cache`, reuses (and fills) the set-up shared with other runs on the same input.
DenoiseReport denoise(Mesh& mesh, const DenoiseOptions& options, const ProgressCallback& progress = {},
                      const IterationObserver& observer = {}, DenoiseCache* cache = nullptr);

/// The input's face normals after `passes` passes of the Tukey filter (width sigma_s, closeness c_a, ball
/// neighbourhoods of radius radius_factor x c_a), in the mesh's face order: what --auto's result check
/// turns faces against. With `cache`, shares its set-up with later denoise() runs on the same mesh.
std::vector<Vec3> prefiltered_normals(const Mesh& mesh, double radius_factor, double sigma_s, int passes,
                                      DenoiseCache* cache = nullptr);

/// Recomputes stored vertex normals (nx, ny, nz), if the mesh has them, from its current faces.
void refresh_stored_normals(Mesh& mesh);

/// RMS distance the vertices moved from `from` to `to` along the vertex normals of `to` (vertices without
/// faces are not counted): what the discrepancy principle (`target_displacement`) compares with the noise.
double normal_displacement(const Topology& topology, const std::vector<Face>& faces, const std::vector<Vec3>& from,
                           const std::vector<Vec3>& to);
/// The same with the face geometry of `to` already at hand (no second copy of it in memory).
double normal_displacement(const Topology& topology, const FaceGeometry& geometry_of_to, const std::vector<Vec3>& from,
                           const std::vector<Vec3>& to);

/// Area-weighted mean (each vertex weighing a third of its faces' area) of the signed distances the
/// vertices moved from `from` to `to` along the vertex normals of `to`. Removing zero-mean noise moves
/// vertices both ways alike and leaves it near 0; a run that shrinks the surface (or swells it) moves
/// them one way: on a closed mesh it is about the change of enclosed volume over the area.
double mean_normal_move(const Topology& topology, const FaceGeometry& geometry_of_to, const std::vector<Vec3>& from,
                        const std::vector<Vec3>& to);

}  // namespace scanmesh
