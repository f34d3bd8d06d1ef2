#pragma once
// How well a mesh represents the points it was made from: what a scanning engineer checks before anything
// else. Distances from the input points to the mesh (in scene units), the share of points the mesh leaves
// out, the holes it has where the scan had data, its pieces and its orientation. The meshing stages use it
// to choose a method and to say when a result is degraded; the report shows it.
#include <cstdint>
#include <string>
#include <vector>

#include "scanmesh/json.h"
#include "scanmesh/mesh.h"

namespace scanmesh {

/// One boundary loop of the mesh, classified.
struct BoundaryLoopFit {
  enum class Kind {
    rim,   ///< the longest loop of an open piece: the edge of what the scanner saw
    gap,   ///< encloses a region without points: the scan saw nothing there
    hole,  ///< encloses points the mesh leaves out, three or more (or is too small to be a gap in the data): a meshing failure
  };
  Kind kind = Kind::rim;
  double perimeter = 0.0;  ///< scene units
  std::size_t vertices = 0;
  std::vector<int> ring;   ///< its vertices in boundary order (against the orientation of the faces on it)
  /// Gaps only: inside the loop, off the mesh, lie points the mesh covers (within the coverage radius):
  /// noise beside the surface, or a sparsely sampled curve the loop cuts across, which a mesh through
  /// the points might have closed. Nothing the scan measured is left out.
  bool points_beside = false;
};

struct ScanFit {
  double spacing = 0.0;                ///< mean point spacing the thresholds are measured in
  std::size_t points = 0;              ///< finite input points
  std::vector<double> point_distance;  ///< each finite input point's distance to the mesh, scene units
  double distance_mean = 0.0, distance_p95 = 0.0, distance_max = 0.0;
  double coverage = 0.0;               ///< share of points within `coverage_radius` of the mesh
  /// Scene units: 2 spacings, or 3 x `scatter` where the scan's noise is larger than that (a point within
  /// the noise band around the surface is represented by it, not left out).
  double coverage_radius = 0.0;
  /// How far the points scatter across the surface, independently of their neighbours (scene units, a
  /// standard deviation): from the differences between the signed distances of points whose closest
  /// points on the mesh are neighbours. Noise differs from point to point; detail the mesh misses (a
  /// smoothed-off ridge, a surface offset from the points) is shared by neighbours and does not count.
  /// 0 for a mesh through its points.
  double scatter = 0.0;
  std::size_t points_left_out = 0;     ///< points farther than coverage_radius
  std::size_t pieces = 0;              ///< connected pieces (through shared vertices)
  double main_piece_share = 0.0;       ///< faces of the largest piece / all faces
  /// Pieces lying over larger ones: at least half of a piece's vertices within `coverage_radius` of a
  /// vertex of a piece with more faces (of equal pieces the one whose first face comes first counts as
  /// larger). The same surface meshed twice: typically a thin sheet or an open shell whose two sides were
  /// scanned, each side's points meshed as a layer of their own. The largest piece never lies over
  /// another, so removing these pieces leaves one layer. Their count, ...
  std::size_t layered_pieces = 0;
  double layered_share = 0.0;                ///< ...their faces / all faces, ...
  std::vector<std::uint8_t> layered_faces;   ///< ...and 1 for each of their faces (empty when there is none)
  std::vector<BoundaryLoopFit> loops;  ///< every closed boundary loop
  std::size_t rims = 0, gaps = 0, holes = 0;
  double largest_hole = 0.0;           ///< perimeter of the largest hole, scene units (0 if none)
  std::size_t inconsistent_edges = 0;  ///< two-face edges whose faces disagree about the orientation
};

/// Measures `mesh` against the `points` it represents (non-finite points are skipped). `spacing` is the
/// cloud's mean point spacing (> 0). With `from_grid` (the mesh was made on a sensor's pixel grid, which
/// connects every pair of neighbouring pixels but across depth jumps, too oblique views and missing
/// pixels) every loop that is not a rim is a gap of the scan. `as_meshed`, if given, is the fit of the mesh
/// as meshing left it, before later stages moved its vertices (denoising): moving vertices opens no loop
/// and changes no region a loop encloses, only which loop is the longest and where the probes fall (a
/// smoothed rim draws back from the noisy points beside it). So a loop that mesh has as well (the same
/// vertices in the same order) keeps its kind; loops a later stage changed are judged again. Parallel;
/// independent of the thread count.
ScanFit measure_scan_fit(const Mesh& mesh, const std::vector<Vec3>& points, double spacing, bool from_grid = false,
                         const ScanFit* as_meshed = nullptr);

/// What a result must reach not to count as degraded.
struct ScanFitLimits {
  double min_coverage = 0.97;          ///< share of points within the coverage radius of the mesh
  double min_hole_perimeter = 8.0;     ///< spacings: shorter holes (a missing triangle or two) are not counted
  std::size_t max_holes = 0;           ///< holes at least min_hole_perimeter long
  std::size_t max_inconsistent_edges = 0;
  /// Faces in pieces lying over another piece (ScanFit::layered_share). Meshes of the shared real clouds
  /// have at most 0.01%, dense virtual scans' stray fragments 0.4%; a sheet scanned from both sides and
  /// meshed by greedy projection 27-44%.
  double max_layered_share = 0.03;
};

/// The coverage radius in words: "2 spacings", or "3 x the points' scatter across the surface, 4.6 spacings".
std::string coverage_radius_words(const ScanFit& fit);

/// The reasons `fit` does not meet `limits`, each one sentence with the numbers; empty when it does.
std::vector<std::string> scan_fit_problems(const ScanFit& fit, const ScanFitLimits& limits = {});

/// The summary numbers (no per-point distances) as a JSON object.
void write_json(JsonWriter& writer, const ScanFit& fit);

/// One line: "coverage 99.2% (12 points left out), distance mean 0.0012 / p95 0.0031 / max 0.02, 1 piece,
/// 0 holes, 2 gaps".
std::string scan_fit_summary(const ScanFit& fit);

}  // namespace scanmesh
