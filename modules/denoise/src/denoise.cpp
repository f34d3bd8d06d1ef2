#include "scanmesh/denoise.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include "scanmesh/boundary_curves.h"
#include "scanmesh/errors.h"
#include "scanmesh/noise_analysis.h"
#include "scanmesh/geometry.h"
#include "scanmesh/memory.h"
#include "scanmesh/normal_filtering.h"
#include "scanmesh/parallel.h"
#include "scanmesh/topology.h"
#include "scanmesh/vertex_update.h"

namespace scanmesh {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

RobustEstimator parse_estimator(const std::string& name) {
  if (name == "tukey") return RobustEstimator::tukey;
  if (name == "gaussian") return RobustEstimator::gaussian;
  if (name == "huber") return RobustEstimator::huber;
  if (name == "lorentzian") return RobustEstimator::lorentzian;
  throw UsageError("unknown robust estimator '" + name + "'; choose tukey, gaussian, huber or lorentzian");
}

NeighbourhoodKind parse_neighbourhood(const std::string& name) {
  if (name == "ball") return NeighbourhoodKind::ball;
  if (name == "connected_ball" || name == "connected-ball") return NeighbourhoodKind::connected_ball;
  throw UsageError("unknown neighbourhood '" + name + "'; choose ball or connected_ball");
}

std::string to_string(RobustEstimator e) {
  switch (e) {
    case RobustEstimator::tukey: return "tukey";
    case RobustEstimator::gaussian: return "gaussian";
    case RobustEstimator::huber: return "huber";
    case RobustEstimator::lorentzian: return "lorentzian";
  }
  return "?";
}

std::string to_string(NeighbourhoodKind k) { return k == NeighbourhoodKind::ball ? "ball" : "connected_ball"; }

void validate(const DenoiseOptions& o) {
  DenoiseOptions::schema().validate(o);
  if (o.sliver_guard > 0.0 && o.sliver_guard < 1.0)
    throw UsageError("sliver_guard must be 0 (off) or at least 1 (a triangle's circumradius is at least 0.577 x its shortest edge, "
                     "so a smaller value would count every triangle as a sliver); got " + format_number(o.sliver_guard));
}

namespace {

// Faces in the order of their centroids along a Morton (Z-order) curve, vertices in the order the faces
// first use them (vertices without faces last): faces that are close in space are close in memory, so
// the neighbourhood loops read a few cache lines instead of one per neighbour. The order depends only on
// the geometry (ties by index), never on the thread count.
struct SpatialOrder {
  std::vector<int> faces;     ///< new face index -> old
  std::vector<int> vertices;  ///< new vertex index -> old
};

std::uint64_t spread_bits(std::uint64_t x) {  // 21 bits -> every third of 63
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

SpatialOrder spatial_order(const Mesh& mesh) {
  const std::size_t nf = mesh.num_faces(), nv = mesh.num_vertices();
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (const Vec3& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = (hi - lo).maxCoeff();
  const double to_grid = extent > 0.0 ? 2097151.0 / extent : 0.0;
  std::vector<std::pair<std::uint64_t, int>> keys(nf);
  const auto n = static_cast<long>(nf);
#pragma omp parallel for schedule(static)
  for (long f = 0; f < n; ++f) {
    const Face& t = mesh.faces[f];
    const Vec3 c = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
    std::uint64_t code = 0;
    for (int k = 0; k < 3; ++k)
      code |= spread_bits(static_cast<std::uint64_t>(std::clamp((c[k] - lo[k]) * to_grid, 0.0, 2097151.0))) << k;
    keys[f] = {code, static_cast<int>(f)};
  }
  std::sort(keys.begin(), keys.end());
  SpatialOrder order;
  order.faces.resize(nf);
  order.vertices.reserve(nv);
  std::vector<std::uint8_t> placed(nv, 0);
  for (std::size_t i = 0; i < nf; ++i) {
    order.faces[i] = keys[i].second;
    for (int v : mesh.faces[keys[i].second])
      if (!placed[v]) {
        placed[v] = 1;
        order.vertices.push_back(v);
      }
  }
  for (std::size_t v = 0; v < nv; ++v)
    if (!placed[v]) order.vertices.push_back(static_cast<int>(v));
  return order;
}

// out[order[i]] = p[i]: positions in spatial order back to the caller's.
void to_caller_order(const std::vector<int>& order, const std::vector<Vec3>& p, std::vector<Vec3>& out) {
  out.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) out[order[i]] = p[i];
}

// FNV-1a over the 8-byte words of the positions and the faces: which mesh a DenoiseCache belongs to.
std::uint64_t fingerprint(const Mesh& mesh) {
  std::uint64_t h = 1469598103934665603ULL;
  auto mix = [&h](std::uint64_t w) { h = (h ^ w) * 1099511628211ULL; };
  mix(mesh.num_vertices());
  mix(mesh.num_faces());
  for (const Vec3& p : mesh.positions)
    for (int k = 0; k < 3; ++k) {
      std::uint64_t w;
      std::memcpy(&w, &p[k], sizeof w);
      mix(w);
    }
  for (const Face& f : mesh.faces) {
    mix(static_cast<std::uint32_t>(f[0]) | static_cast<std::uint64_t>(static_cast<std::uint32_t>(f[1])) << 32);
    mix(static_cast<std::uint32_t>(f[2]));
  }
  return h;
}

// The mesh in spatial order.
Mesh in_spatial_order(const Mesh& mesh, const SpatialOrder& order) {
  const std::size_t nv = mesh.num_vertices(), nf = mesh.num_faces();
  std::vector<int> new_index(nv);
  for (std::size_t i = 0; i < nv; ++i) new_index[order.vertices[i]] = static_cast<int>(i);
  Mesh local;
  local.positions.resize(nv);
  for (std::size_t i = 0; i < nv; ++i) local.positions[i] = mesh.positions[order.vertices[i]];
  local.faces.resize(nf);
  for (std::size_t i = 0; i < nf; ++i)
    for (int k = 0; k < 3; ++k) local.faces[i][k] = new_index[mesh.faces[order.faces[i]][k]];
  return local;
}

// The power of two that brings the largest coordinate into [1, 2): scaling by it is exact.
double unit_scale(const std::vector<Vec3>& positions) {
  double largest = 0.0;
  for (const auto& p : positions) largest = std::max(largest, p.cwiseAbs().maxCoeff());
  return largest > 0.0 ? std::ldexp(1.0, -std::ilogb(largest)) : 1.0;
}

}  // namespace

struct DenoiseCache::State {
  std::uint64_t fingerprint = 0;
  SpatialOrder order;
  // Ball neighbourhoods of the input (spatial order, unit scale) at `radius` with at most `max_size` faces.
  bool has_neighbourhoods = false;
  double radius = 0.0;
  int max_size = 0;
  PackedRows neighbourhoods;
  std::size_t capped = 0;
  // The input's connectivity in spatial order (it does not depend on the scale or the options), left by
  // prefiltered_normals() for the next run, which takes it (a run trims what it holds). A run copies it
  // instead only while the caller asks (DenoiseCache::keep_topology; --auto on small meshes): holding a
  // copy adds ~80 bytes per face to --auto's peak.
  std::unique_ptr<Topology> topology;
  bool keep_topology = false;  // DenoiseCache::keep_topology, for the run in progress
  double boundary_noise = -1.0;  // the input's noise across its boundary curves (unit scale), once measured
};

DenoiseCache::DenoiseCache() = default;
DenoiseCache::~DenoiseCache() = default;
std::size_t DenoiseCache::cached_neighbours() const { return state ? state->neighbourhoods.entries() : 0; }

namespace {

// The cache's state for `mesh` (reset if it held another mesh's), or null without a cache.
DenoiseCache::State* cache_for(DenoiseCache* cache, const Mesh& mesh) {
  if (cache == nullptr) return nullptr;
  const std::uint64_t fp = fingerprint(mesh);
  if (!cache->state || cache->state->fingerprint != fp) {
    cache->state = std::make_unique<DenoiseCache::State>();
    cache->state->fingerprint = fp;
    cache->state->order = spatial_order(mesh);
  }
  return cache->state.get();
}

// The spatial order of `mesh`: the cache's (bound to `mesh` first if it held another one), or computed
// into `own` without a cache. Sets *cached to the cache's state, or null.
const SpatialOrder& order_of(const Mesh& mesh, DenoiseCache* cache, DenoiseCache::State** cached, SpatialOrder& own) {
  *cached = cache_for(cache, mesh);
  if (*cached != nullptr) return (*cached)->order;
  own = spatial_order(mesh);
  return own;
}

// The input's neighbourhoods: the cache's when it holds them at this radius, else built into the cache
// (or into `own` without one). The cache's table is used in place, not copied.
const PackedRows& input_neighbourhoods(DenoiseCache::State* cached, const Topology& topology, const FaceGeometry& geometry,
                                       double radius, NeighbourhoodKind kind, int max_size, std::size_t* capped, PackedRows& own) {
  const bool usable = cached != nullptr && kind == NeighbourhoodKind::ball;
  if (usable && cached->has_neighbourhoods && cached->radius == radius && cached->max_size == max_size) {
    *capped = cached->capped;
    return cached->neighbourhoods;
  }
  PackedRows& out = usable ? cached->neighbourhoods : own;
  if (usable) cached->has_neighbourhoods = false;
  out = PackedRows{};  // the old table goes before the new one is built
  out = packed_face_neighbourhoods(topology, geometry, radius, kind, max_size, capped, true);
  if (usable) {
    cached->has_neighbourhoods = true;
    cached->radius = radius;
    cached->max_size = max_size;
    cached->capped = *capped;
  }
  return out;
}

// `mesh`'s topology: the one the cache holds for it, taken out of the cache, or built (face_faces only
// `with_face_faces`).
Topology take_topology(DenoiseCache::State* cached, const Mesh& mesh, bool with_face_faces) {
  if (cached == nullptr || !cached->topology) return build_topology(mesh, with_face_faces);
  Topology t = cached->keep_topology ? *cached->topology : std::move(*cached->topology);
  if (!cached->keep_topology) cached->topology.reset();
  if (with_face_faces && t.face_faces.rows() != mesh.num_faces()) add_face_faces(t, mesh.num_faces());  // (the cache's is built without)
  return t;
}

// How far a boundary loop may move across its curve (BoundaryDrift): sqrt 2 x the noise along the normals
// (the noise's two components across a curve), as the mesh reads it. Measured once per input: --auto's
// runs on the same mesh take it from the cache.
double boundary_noise(DenoiseCache::State* cached, const Mesh& mesh, const Topology& topology, const FaceGeometry& geometry) {
  if (cached != nullptr && cached->boundary_noise >= 0.0) return cached->boundary_noise;
  const NoiseAnalysis noise = analyse_noise(mesh, topology, geometry);
  const double across = std::sqrt(2.0) * noise.level * noise.mean_edge;
  if (cached != nullptr) cached->boundary_noise = across;
  return across;
}

// An observer of the run in spatial order: the positions at unit scale and the scale (divide to get the
// caller's units), so the caller's copy is made once, in its own order.
using ScaledObserver = std::function<bool(int iteration, const std::vector<Vec3>& scaled, double scale)>;

// Leaves mesh.positions as they were and sets *nonfinite to a vertex if the result is not finite.
DenoiseReport denoise_in_order(Mesh& mesh, const DenoiseOptions& options, const ProgressCallback& progress,
                               const ScaledObserver& observer, long* nonfinite, DenoiseCache::State* cached) {
  DenoiseReport report;
  *nonfinite = -1;

  // Work at unit scale: coordinates of 1e-150 or 1e80 behave like those of the unit box (squared
  // distances neither underflow nor overflow). The scale is a power of two, so scaling and unscaling are
  // exact and every result equals the one computed at the original scale.
  const double scale = unit_scale(mesh.positions);
  struct Unscale {
    Mesh& m;
    double s;
    ~Unscale() {
      for (auto& p : m.positions) p /= s;
    }
  } restore{mesh, scale};
  for (auto& p : mesh.positions) p *= scale;

  Topology topology = take_topology(cached, mesh, options.neighbourhood == NeighbourhoodKind::connected_ball);
  BoundaryCurves curves;
  const bool boundary = options.keep_boundary && topology.num_boundary_edges() > 0;
  if (boundary) curves = build_boundary_curves(mesh, topology);
  for (auto b : topology.boundary_vertex) report.boundary_vertices += b;

  FaceGeometry geometry;
  compute_face_geometry(mesh.positions, mesh.faces, geometry);
  report.exact_plane_fraction = exact_plane_fraction(mesh, topology, geometry);

  // A boundary moves across its curve by at most the noise there. Not under impulsive noise, whose moving
  // vertices are off by impulses rather than by the noise.
  BoundaryDrift drift;
  if (boundary && options.outlier_jump <= 0.0) {
    drift.input = &mesh.positions;
    drift.max_rms = boundary_noise(cached, mesh, topology, geometry);
  }

  const double c_a = mean_centroid_distance(mesh, topology, geometry);
  report.mean_centroid_distance = c_a;
  if (!(c_a > 0.0)) return report;  // every face degenerate: nothing to filter

  // Impulsive noise: only the outliers (height jump above outlier_jump x the median) move, on the boundary
  // those off their curve; vertices neither test can judge (fewer than three neighbours, boundary corners,
  // ragged loops) stay.
  std::vector<std::uint8_t> fixed;
  if (options.outlier_jump > 0.0) {
    const std::vector<double> jump = vertex_jumps(mesh, topology, geometry);
    if (std::any_of(jump.begin(), jump.end(), [](double j) { return j >= 0.0; })) {
      fixed = outlier_vertices(mesh, topology, geometry, jump, options.outlier_jump, options.outlier_peaks);
      // Boundary vertices, which the jump cannot judge, are judged along their curves (found for this
      // even when the boundary is not kept as curves); those on no curve (corners, irregular or ragged
      // loops) stay.
      std::vector<std::uint8_t> along;
      if (boundary) along = boundary_outliers(mesh.positions, curves, options.outlier_jump);
      else if (topology.num_boundary_edges() > 0)
        along = boundary_outliers(mesh.positions, build_boundary_curves(mesh, topology), options.outlier_jump);
      for (std::size_t v = 0; v < fixed.size(); ++v) {
        const bool outlier = fixed[v] || (!along.empty() && along[v]);
        fixed[v] = outlier ? 0 : 1;
      }
    }
  }
  // The discrepancy principle: stop once the RMS displacement along the vertex normals reaches the target.
  const double target = options.target_displacement * mean_edge_length(mesh, topology);
  // From here on only vertex_faces and the boundary flags of the topology are needed (and face_faces for
  // connected-ball neighbourhoods): the rest, ~70 bytes per face, goes before the neighbourhoods are built.
  const PackedRows fidelity = PackedRows::from(fidelity_neighbours(mesh, topology));  // may take topology.vertex_vertices
  release(topology.vertex_vertices);
  release(topology.edges);
  release(topology.edge_faces);
  release(topology.face_edges);
  if (options.neighbourhood == NeighbourhoodKind::ball) release(topology.face_faces);
  return_free_memory();

  auto t0 = std::chrono::steady_clock::now();
  PackedRows own_neighbourhoods;
  const PackedRows* neighbourhoods = &input_neighbourhoods(cached, topology, geometry, options.radius_factor * c_a, options.neighbourhood,
                                                          max_neighbourhood_size(options.radius_factor), &report.capped_neighbourhoods,
                                                          own_neighbourhoods);
  report.mean_neighbourhood_size = static_cast<double>(neighbourhoods->entries()) / static_cast<double>(mesh.num_faces());
  return_free_memory();  // the k-d tree's result rows
  report.seconds_neighbourhoods += seconds_since(t0);
  // The working copy of the positions is made only now, after the neighbourhood search's peak.
  std::vector<Vec3> positions = mesh.positions, updated;
  // `geometry` is always that of `positions` here (recomputed at the end of every iteration).
  auto displacement = [&] { return normal_displacement(topology, geometry, mesh.positions, positions); };

  // The face normals are filtered in place: until the geometry is recomputed at the end of the iteration
  // only the vertex update reads it, and that takes the centroids and areas.
  std::vector<Vec3>& filtered = geometry.normals;
  FilterWork work;
  // The Tukey kernel and the vertex update compute each face's centroid from the positions as they need
  // it (the same bits), so the iterations do not hold a table of them (24 bytes a face); the other
  // estimators and per-iteration neighbourhood searches read the table.
  const bool lean = options.estimator == RobustEstimator::tukey && !options.recompute_neighbourhoods;
  std::vector<std::uint8_t> slivers;  // per face, for the sliver guard (filled every iteration)
  std::size_t new_slivers = 0;
  if (lean) {
    work.positions = &positions;
    work.faces = &mesh.faces;
    std::vector<Vec3>().swap(geometry.centroids);
    new_slivers = refresh_faces(positions, mesh.positions, mesh.faces, options.sliver_guard, geometry, work, slivers);
  }
  double lambda = options.lambda;
  VertexUpdateTerms terms;
  terms.boundary = boundary ? &curves : nullptr;
  terms.feature_aware = options.feature_aware_fidelity;
  report.stop_reason = "iterations";
  for (int it = 0; it < options.iterations; ++it) {
    if (options.recompute_neighbourhoods && it > 0) {
      t0 = std::chrono::steady_clock::now();
      own_neighbourhoods = PackedRows{};
      own_neighbourhoods = packed_face_neighbourhoods(topology, geometry, options.radius_factor * c_a, options.neighbourhood,
                                               max_neighbourhood_size(options.radius_factor), nullptr, true);
      neighbourhoods = &own_neighbourhoods;
      report.seconds_neighbourhoods += seconds_since(t0);
    }
    t0 = std::chrono::steady_clock::now();
    filter_face_normals(geometry, *neighbourhoods, c_a, options.sigma_s, options.estimator, filtered, nullptr, &work);
    report.seconds_filtering += seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    terms.lambda = lambda;
    const bool guard = options.sliver_guard > 0.0 &&
                       (lean ? new_slivers : mark_new_slivers(positions, mesh.positions, mesh.faces, options.sliver_guard, slivers)) > 0;
    terms.slivers = guard ? &slivers : nullptr;
    update_vertices(positions, topology, fidelity, geometry, filtered, terms, updated, &mesh.faces);
    positions.swap(updated);
    if (boundary)
      // Under impulsive noise the vertices that move (outliers, on the boundary those off their curve) are
      // off by impulses, not by noise, so the curve fit moves them along the curve too; the fixed ones are
      // put back below whatever the fit did.
      smooth_boundary_curves(positions, mesh.faces, topology, curves, options.boundary_window, !fixed.empty(), &drift);
    if (!fixed.empty())
      for (std::size_t v = 0; v < positions.size(); ++v)
        if (fixed[v]) positions[v] = mesh.positions[v];
    // For the next iteration and the stop rule.
    if (lean) new_slivers = refresh_faces(positions, mesh.positions, mesh.faces, options.sliver_guard, geometry, work, slivers);
    else compute_face_geometry(positions, mesh.faces, geometry, true);
    report.seconds_vertex_update += seconds_since(t0);
    lambda *= options.decay;
    ++report.iterations;
    if (progress) progress(it + 1, options.iterations);
    if (target > 0.0 && (report.displacement = displacement()) >= target) {
      report.stop_reason = "target displacement";
      break;
    }
    if (observer) {
      if (!observer(it + 1, positions, scale)) {
        report.stop_reason = "observer";
        break;
      }
    }
  }
  if (boundary) report.boundary_loops = curves.loop_edges.rows();
  report.boundary_loops_stopped = static_cast<std::size_t>(std::count(drift.stopped.begin(), drift.stopped.end(), std::uint8_t{1}));
  if (target <= 0.0) report.displacement = displacement();
  report.displacement /= scale;
  for (std::size_t v = 0; v < positions.size(); ++v)
    if (!positions[v].allFinite()) {
      *nonfinite = static_cast<long>(v);
      return report;
    }
  mesh.positions = std::move(positions);
  return report;
}

}  // namespace

DenoiseReport denoise(Mesh& mesh, const DenoiseOptions& options, const ProgressCallback& progress,
                      const IterationObserver& observer, DenoiseCache* cache) {
  validate(options);
  if (mesh.faces.empty() || options.iterations == 0) return DenoiseReport{};
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v)
    if (!mesh.positions[v].allFinite())
      throw InputError("denoise: vertex " + std::to_string(v) + " has a coordinate that is NaN or infinite");

  // The work runs on a copy in spatial order; the results go back to the caller's order. The caller's
  // positions are set aside meanwhile (an observer gets the run's as its argument), and so are its faces
  // unless there is an observer (which may read them), so a large mesh is not held twice; they are
  // rebuilt from the copy, exactly, however the run ends.
  DenoiseCache::State* cached = nullptr;
  SpatialOrder own_order;
  const SpatialOrder& order = order_of(mesh, cache, &cached, own_order);
  if (cached != nullptr) cached->keep_topology = cache->keeps_topology();
  Mesh local = in_spatial_order(mesh, order);
  struct GiveBack {
    Mesh& caller;
    const Mesh& local;
    const SpatialOrder& order;
    bool faces_aside = false, positions_aside = false;
    void operator()() {  // the caller's faces if set aside, and its positions unless they have been set
      if (faces_aside) {
        faces_aside = false;
        caller.faces.resize(local.faces.size());
        for (std::size_t i = 0; i < local.faces.size(); ++i)
          for (int k = 0; k < 3; ++k) caller.faces[order.faces[i]][k] = order.vertices[local.faces[i][k]];
      }
      if (positions_aside) {
        positions_aside = false;
        if (caller.positions.empty()) to_caller_order(order.vertices, local.positions, caller.positions);
      }
    }
    ~GiveBack() { (*this)(); }
  } give_back{mesh, local, order};
  std::vector<Vec3>().swap(mesh.positions);
  give_back.positions_aside = true;
  if (!observer) {
    std::vector<Face>().swap(mesh.faces);
    give_back.faces_aside = true;
  }
  std::vector<Vec3> seen;  // the run's positions in the caller's order and units
  ScaledObserver in_order;
  if (observer)
    in_order = [&](int it, const std::vector<Vec3>& p, double scale) {
      seen.resize(p.size());
      for (std::size_t i = 0; i < p.size(); ++i) seen[order.vertices[i]] = p[i] / scale;
      return observer(it, seen);
    };
  long nonfinite = -1;
  const DenoiseReport report = denoise_in_order(local, options, progress, in_order, &nonfinite, cached);
  if (nonfinite >= 0)  // local.positions are still the input, and so are the caller's (or GiveBack's)
    throw InputError("denoise: the result has non-finite coordinates (vertex " + std::to_string(order.vertices[nonfinite]) +
                     "); the input was left as it was");
  std::vector<Vec3>().swap(seen);
  to_caller_order(order.vertices, local.positions, mesh.positions);
  give_back();

  // Stored vertex normals describe the old surface; replace them with the new one's.
  refresh_stored_normals(mesh);
  return report;
}

std::vector<Vec3> prefiltered_normals(const Mesh& mesh, double radius_factor, double sigma_s, int passes, DenoiseCache* cache) {
  DenoiseCache::State* cached = nullptr;
  SpatialOrder own_order;
  const SpatialOrder& order = order_of(mesh, cache, &cached, own_order);
  // The same frame as denoise(): spatial order, unit scale (so the neighbourhoods are the ones its runs use).
  Mesh local = in_spatial_order(mesh, order);
  const double scale = unit_scale(local.positions);
  for (auto& p : local.positions) p *= scale;
  // Built into the cache (the next run takes it from there), or kept here without one.
  std::unique_ptr<Topology> own;
  std::unique_ptr<Topology>& slot = cached != nullptr ? cached->topology : own;
  if (!slot) slot = std::make_unique<Topology>(build_topology(local, false));  // (take_topology adds face_faces if a run needs them)
  const Topology& topology = *slot;
  FaceGeometry g;
  compute_face_geometry(local.positions, local.faces, g);
  const double c_a = mean_centroid_distance(local, topology, g);
  if (c_a > 0.0) {
    std::size_t capped = 0;
    PackedRows own_neighbourhoods;
    const PackedRows& nbh = input_neighbourhoods(cached, topology, g, radius_factor * c_a, NeighbourhoodKind::ball,
                                                max_neighbourhood_size(radius_factor), &capped, own_neighbourhoods);
    FilterWork work;
    for (int pass = 0; pass < passes; ++pass) filter_face_normals(g, nbh, c_a, sigma_s, RobustEstimator::tukey, g.normals, nullptr, &work);
  }
  std::vector<Vec3> out(g.normals.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[order.faces[i]] = g.normals[i];
  return out;
}

void refresh_stored_normals(Mesh& mesh) {
  VertexProperty* nx = mesh.find_property("nx");
  VertexProperty* ny = mesh.find_property("ny");
  VertexProperty* nz = mesh.find_property("nz");
  if (!(nx && ny && nz)) return;
  FaceGeometry geometry;
  compute_face_geometry(mesh.positions, mesh.faces, geometry);
  const std::vector<Vec3> normals = vertex_normals(build_topology(mesh), geometry);
  for (std::size_t v = 0; v < normals.size(); ++v) {
    nx->values[v] = normals[v][0];
    ny->values[v] = normals[v][1];
    nz->values[v] = normals[v][2];
  }
}

double normal_displacement(const Topology& topology, const std::vector<Face>& faces, const std::vector<Vec3>& from,
                           const std::vector<Vec3>& to) {
  FaceGeometry geometry;
  compute_face_geometry(to, faces, geometry);
  return normal_displacement(topology, geometry, from, to);
}

double normal_displacement(const Topology& topology, const FaceGeometry& geometry, const std::vector<Vec3>& from,
                           const std::vector<Vec3>& to) {
  // Each vertex normal as it is needed: a table of them was the denoiser's peak memory on large meshes.
  // (sum of squares, vertices with faces)
  const long vertices = static_cast<long>(to.size());
  const Eigen::Vector2d s = ordered_sum(vertices, Eigen::Vector2d(0, 0), [&](long v) {
    const auto u = static_cast<std::size_t>(v);
    // The faces are reached through each vertex's list, not in their order: fetched a few vertices ahead.
    constexpr long kAhead = 8;
    if (v + kAhead < vertices)
      for (const int* f = topology.vertex_faces.begin(u + kAhead); f != topology.vertex_faces.end(u + kAhead); ++f) {
        __builtin_prefetch(&geometry.normals[*f]);
        __builtin_prefetch(&geometry.areas[*f]);
      }
    if (topology.vertex_faces.size(u) == 0) return Eigen::Vector2d(0, 0);
    const double d = (to[u] - from[u]).dot(vertex_normal(topology, geometry, u));
    return Eigen::Vector2d(d * d, 1.0);
  });
  return s[1] > 0 ? std::sqrt(s[0] / s[1]) : 0.0;
}

double mean_normal_move(const Topology& topology, const FaceGeometry& geometry, const std::vector<Vec3>& from, const std::vector<Vec3>& to) {
  // (sum of area x signed move, sum of area)
  const Eigen::Vector2d s = ordered_sum(static_cast<long>(to.size()), Eigen::Vector2d(0, 0), [&](long v) {
    const auto u = static_cast<std::size_t>(v);
    double area = 0.0;
    for (const int* f = topology.vertex_faces.begin(u); f != topology.vertex_faces.end(u); ++f) area += geometry.areas[*f];
    if (area <= 0.0) return Eigen::Vector2d(0, 0);
    return Eigen::Vector2d(area * (to[u] - from[u]).dot(vertex_normal(topology, geometry, u)), area);
  });
  return s[1] > 0 ? s[0] / s[1] : 0.0;
}

}  // namespace scanmesh
