#include "scanmesh/auto_denoise.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scanmesh/geometry.h"
#include "scanmesh/memory.h"
#include "scanmesh/noise_analysis.h"
#include "scanmesh/normal_filtering.h"
#include "scanmesh/parallel.h"
#include "scanmesh/topology.h"

namespace scanmesh {
namespace {

const char* plural(int n) { return n == 1 ? "" : "s"; }  // "1 iteration", "14 iterations"

// Share of manifold edges whose faces' normals differ by an angle in (min_deg, max_deg] (bend_share) at
// `positions`: soft creases for (20, 45]. Real features of machined parts are sharper; noise a
// feature-keeping filter locked in is not.
double soft_crease_share(const std::vector<Vec3>& positions, const Mesh& mesh, const Topology& topo, double min_deg, double max_deg) {
  FaceGeometry g;
  compute_face_geometry(positions, mesh.faces, g, false);
  return bend_share(g, topo, min_deg, max_deg);
}

double enclosed_volume(const std::vector<Vec3>& p, const std::vector<Face>& faces) {
  double v = 0.0;
  for (const Face& f : faces) v += p[f[0]].dot(p[f[1]].cross(p[f[2]]));
  return v / 6.0;
}

}  // namespace

double bend_share(const FaceGeometry& g, const Topology& topo, double min_deg, double max_deg) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  const double lo = min_deg < 0.0 ? 2.0 : std::cos(min_deg * kDeg), hi = std::cos(max_deg * kDeg);
  // (edges bending so far, manifold edges): counts, so any order gives the same
  const long edges = static_cast<long>(topo.edges.size());
  const Eigen::Vector2d n = ordered_sum(edges, Eigen::Vector2d(0, 0), [&](long e) {
    // The normals are reached in the edges' order, not the faces': fetched a few edges ahead.
    constexpr long kAhead = 16;
    if (e + kAhead < edges && topo.edge_faces.size(static_cast<std::size_t>(e + kAhead)) == 2) {
      const int* ahead = topo.edge_faces.begin(static_cast<std::size_t>(e + kAhead));
      __builtin_prefetch(&g.normals[ahead[0]]);
      __builtin_prefetch(&g.normals[ahead[1]]);
    }
    if (topo.edge_faces.size(static_cast<std::size_t>(e)) != 2) return Eigen::Vector2d(0, 0);
    const int* f = topo.edge_faces.begin(static_cast<std::size_t>(e));
    const double c = g.normals[f[0]].dot(g.normals[f[1]]);
    return Eigen::Vector2d(c < lo && c >= hi ? 1.0 : 0.0, 1.0);
  });
  return n[1] > 0 ? n[0] / n[1] : 0.0;
}

double turned_area_share(const FaceGeometry& g, const std::vector<Vec3>& reference) {
  // (turned area, total area)
  const Eigen::Vector2d a = ordered_sum(static_cast<long>(g.normals.size()), Eigen::Vector2d(0, 0), [&](long f) {
    return Eigen::Vector2d(g.normals[f].dot(reference[f]) < 0.0 ? g.areas[f] : 0.0, g.areas[f]);
  });
  return a[1] > 0.0 ? a[0] / a[1] : 0.0;
}

AutoReport denoise_auto(Mesh& mesh, const DenoiseOptions& given, const std::vector<std::string>& explicit_fields,
                        const AutoRules& rules, const ProgressCallback& progress) {
  AutoReport r;
  auto is_given = [&](const char* name) { return std::find(explicit_fields.begin(), explicit_fields.end(), name) != explicit_fields.end(); };
  DenoiseOptions o = given;
  o.automatic = true;
  if (!is_given("radius_factor")) o.radius_factor = rules.radius_factor;
  r.options = o;
  validate(o);
  if (mesh.faces.empty()) {
    r.mode = "untouched";
    r.reason = "no faces";
    return r;
  }
  // Held through the runs, so kept lean: vertex_vertices and face_faces, which only the noise analysis
  // and the unfolding after the runs read, are built when those need them, and face_edges not at all.
  // The input's face geometry (no centroids: nothing here reads them) is computed where it is needed
  // rather than held (32 bytes a face): a large mesh's peak is the set-up and the runs in between.
  Topology topo = build_topology(mesh, false);
  auto geometry_of = [&](const std::vector<Vec3>& positions) {
    FaceGeometry g;
    compute_face_geometry(positions, mesh.faces, g, false);
    return g;
  };
  bool has_area = false;
  const NoiseAnalysis na = [&] {
    const FaceGeometry geometry = geometry_of(mesh.positions);
    has_area = std::any_of(geometry.areas.begin(), geometry.areas.end(), [](double a) { return a > 0.0; });
    return analyse_noise(mesh, topo, geometry);
  }();
  release(topo.vertex_vertices);
  release(topo.face_edges);
  r.noise_level = na.level;
  r.noise = rules.noise_statistic == NoiseStatistic::median ? na.median_jump
            : rules.noise_statistic == NoiseStatistic::rms  ? na.rms_jump
                                                            : na.trimmed_rms_jump;
  r.exact_plane_fraction = na.exact_plane_fraction;
  r.impulsive_share = na.isolated_outlier_share;
  r.height_agreement = na.height_agreement;
  const double edge = na.mean_edge > 0.0 ? na.mean_edge : 1.0;
  char line[512];

  // What the result check compares against: the input's normals after four passes of the wide filter
  // (noise flips a face relative to its own neighbourhood, denoising must not). Its neighbourhoods (and
  // the spatial order) are the ones both runs below use, so they are built once.
  DenoiseCache cache;
  const std::vector<Vec3> reference = prefiltered_normals(mesh, 3.0, 2.0, 4, &cache);
  const double input_turned = turned_area_share(geometry_of(mesh.positions), reference);
  // The input's positions: every run starts from them (and the result is measured against them).
  const std::vector<Vec3> input = mesh.positions;
  const bool closed = topo.num_boundary_edges() == 0 && topo.num_nonmanifold_edges() == 0;
  const double input_volume = closed ? enclosed_volume(mesh.positions, mesh.faces) : 0.0;
  // A limit of 1e9 or more is off (the default): no volume is measured then.
  const bool volume_checked = closed && std::abs(input_volume) > 0.0 && rules.max_volume_change < 1e9;
  const int cap = is_given("iterations") ? o.iterations : rules.max_iterations;

  // Runs `opt` on `m` with the result check after every iteration: an iteration passes unless it has more
  // of the surface (by area) turned against the smoothed input than the input has, or a closed mesh's
  // volume changed by more than the limit. A run goes on through failing iterations (the first steps on a
  // scan's rough triangulation turn slivers and small facets that later ones straighten), until
  // rules.check_patience of them in a row follow one that passed, and keeps the last iteration that
  // passed (the input if none did). The discrepancy target ends it, unless `probe`
  // (asked after every iteration, with the face geometry the check computed) lifts it; the probe may
  // also end the run.
  enum class Probe { go_on, stop, no_target };
  using ProbeFn = std::function<Probe(int, const FaceGeometry&)>;
  // With `while_falling`, the target does not end the run while the soft creases are still falling fast
  // (below rules.crease_fall x their share at half the iterations): the filter is still taking noise out.
  //
  // With `while_falling` (the feature-keeping run) the plateau rule applies too: reaching the target at
  // iteration t, the run looks on to plateau_end(t); if its displacement grew by less than
  // rules.plateau_growth of itself meanwhile, the surface has levelled off (flat and developable parts keep
  // improving while nothing more moves) and the run goes on without a target (`levelled_at` = t);
  // otherwise it returns iteration t. The probe is not asked after the target, but `ends_at_target` is,
  // before looking on, with what the run keeps at the target: true ends the run there (a mesh the probe
  // would call smooth need not run on).
  // Soft creases above this share at the probe: a smooth shape (noise the narrow kernel locked in). The
  // wide kernel's continuation needs more than this too (AutoRules::smooth_crease_fall).
  const double crease_limit = rules.crease_share + rules.crease_share_per_level * na.level;
  // ...on a triangulation of scanned points a lower floor (AutoRules::points_crease_floor).
  const double fall_floor = o.vertices_are_points && rules.points_crease_floor >= 0.0 ? std::min(crease_limit, rules.points_crease_floor)
                                                                                      : crease_limit;
  int levelled_at = 0;
  bool fall_off = false;  // set by the probe: too few flat edges for the crease-fall continuation
  int ran_past_target = 0;  // where the continuation first kept the run going past its target
  bool past_target_by_bends = false;  // ...because every bend was falling fast, not the soft creases alone
  int flat_floor_from = 0;  // where the flat floor kept the run going past its target
  int flat_floor_to = 0;    // ...and the iteration it went on to
  bool flat_floor_grown = false;  // ...ended there by the floor's growth limit
  using TargetFn = std::function<bool(const std::vector<Vec3>&, int kept_iteration)>;
  // `smooth_fall` (a run without `while_falling`: the wide kernel's): the target does not end the run while
  // the soft creases are below this x their share at half the iterations either (0: it does).
  auto checked_run = [&](Mesh& m, const DenoiseOptions& opt, const ProbeFn& probe, bool while_falling,
                         const TargetFn& ends_at_target = {}, double smooth_fall = 0.0) {
    const std::vector<Vec3>& start = input;  // every run starts from the input
    const double target = opt.target_displacement * edge;
    bool target_on = target > 0.0, reached = false;
    DenoiseOptions inner = opt;
    inner.target_displacement = 0.0;  // applied below, where the probe can lift it
    std::vector<Vec3> accepted = m.positions;
    std::string verdict = "passed";
    int last_pass = 0;
    double last_turned = input_turned;
    double last_volume_change = 0.0;  // of the last iteration, when measured
    bool volume_failed = false;       // the last iteration failed on the volume, not on turned surface
    FaceGeometry at;
    std::vector<double> creases_at;  // by iteration (index 0: not measured)
    std::vector<double> bends_at;    // every bend over the soft creases' lower limit, likewise (wide run on scanned points)
    const bool track_bends = !while_falling && o.vertices_are_points && rules.points_bend_fall;
    const double fall = while_falling ? rules.crease_fall : smooth_fall;
    const bool track = fall > 0.0 && target_on;
    const bool plateau = while_falling && target_on && rules.plateau_growth > 0.0;
    // The flat floor (AutoRules::flat_floor_share): the iteration a run that reached its target on a
    // mostly flat surface goes on to (0: none), and what it keeps there if it looks on past it.
    const bool floor_rule = while_falling && target_on && rules.flat_floor_share > 0.0 && rules.flat_floor_iterations > 0;
    int floor_at = 0;
    bool plateau_judged = false, floored = false;
    std::vector<double> moved;  // normal displacement by iteration (index 0: the input, 0)
    int target_it = 0;          // where the target was reached, while the plateau rule looks on (plateau_end)
    bool revert = false;
    struct Snapshot {
      std::vector<Vec3> accepted;
      int last_pass = 0;
      double last_turned = 0.0, last_volume_change = 0.0;
      bool volume_failed = false;
    } at_target, at_floor;
    // Whether the displacement levelled off between target_it and `it`.
    auto levelled = [&](int it) {
      const double d_t = moved[static_cast<std::size_t>(target_it)];
      return moved[static_cast<std::size_t>(it)] - d_t < rules.plateau_growth * d_t;
    };
    DenoiseReport rep = denoise(m, inner, progress, [&](int it, const std::vector<Vec3>& pos) {
      compute_face_geometry(pos, m.faces, at, false);  // one pass for the check and the displacement (no centroids)
      const double turned = turned_area_share(at, reference);
      bool fails = turned > std::max(input_turned, rules.turned_slack);
      volume_failed = false;
      if (!fails && volume_checked) {
        last_volume_change = std::abs(enclosed_volume(pos, m.faces) - input_volume) / std::abs(input_volume);
        fails = volume_failed = last_volume_change > rules.max_volume_change;
      }
      if (!fails) {
        last_pass = it;
        accepted = pos;
      }
      last_turned = turned;
      // Once iterations have passed, a run whose last `check_patience` iterations all failed is turning
      // surface and ends: what it keeps stays the last iteration that passed.
      if (fails && last_pass > 0 && rules.check_patience > 0 && it - last_pass >= rules.check_patience) return false;
      // Nor does a run none of whose first `check_patience` iterations passed go on (on the corpus's
      // curves every run that passes at all passes by iteration 5): its input is what it keeps.
      if (fails && last_pass == 0 && rules.check_patience > 0 && it >= rules.check_patience) return false;
      if (track && target_on) {
        creases_at.resize(static_cast<std::size_t>(it) + 1, -1.0);
        creases_at[it] = bend_share(at, topo, rules.soft_crease_min_deg, rules.soft_crease_max_deg);
        if (track_bends) {
          bends_at.resize(static_cast<std::size_t>(it) + 1, -1.0);
          bends_at[it] = bend_share(at, topo, rules.soft_crease_min_deg, 180.0);
        }
      }
      // The probe is asked before the target (not once the target has been reached), so a run that
      // reaches its target at the probe's own iteration is judged by every rule of the probe, not by the
      // crease share alone.
      if (probe && target_it == 0) {
        const Probe next = probe(it, at);
        if (next == Probe::stop) return false;
        if (next == Probe::no_target) target_on = false;
      }
      if (target_on) {
        const double d = normal_displacement(topo, at, start, pos);
        if (plateau || floor_rule) {
          moved.resize(static_cast<std::size_t>(it) + 1, 0.0);
          moved[static_cast<std::size_t>(it)] = d;
        }
        if (target_it > 0) {  // the plateau rule (and the flat floor) look on from the target
          // The floor's growth limit: a surface still moving this much is losing its shape, not noise.
          if (floor_at > it && rules.flat_floor_growth > 0.0) {
            const double d_t = moved[static_cast<std::size_t>(target_it)];
            if (d - d_t > rules.flat_floor_growth * d_t) floor_at = it;
          }
          if (plateau && !plateau_judged) {
            const bool still_level = levelled(it);
            if (it < plateau_end(target_it, rules.plateau_span)) {
              // The look-ahead goes past the floor: what the run keeps there, in case it ends there.
              if (it == floor_at) at_floor = Snapshot{accepted, last_pass, last_turned, last_volume_change, volume_failed};
              // A displacement already grown past the limit is not waited out (up to half the run again):
              // decided now, as at plateau_end unless the displacement fell back meanwhile, which these runs'
              // displacement does not (the same bytes on every corpus pair).
              if (still_level) return true;
            } else if (still_level) {
              levelled_at = target_it;
              target_on = false;
              return true;
            }
            plateau_judged = true;
          }
          if (floor_at > 0) {
            if (it < floor_at) return true;
            floored = true;  // keeps iteration floor_at
            return false;
          }
          revert = true;
          return false;
        }
        if (d >= target) {
          // (fall_off, set by the feature-keeping run's probe, is that run's own)
          // On scanned points whose first iteration left more edges bent over the soft band than in it (noise
          // wider than the spacing: hard creases feed the soft band as they soften), every bend counts
          // (AutoRules::points_bend_fall), and the run goes on while the hard creases alone are above the
          // probe's limit (AutoRules::points_hard_floor).
          const bool soft_falling = track && it / 2 >= 1 && creases_at[it] < fall * creases_at[it / 2];
          auto hard = [&](int k) { return bends_at[static_cast<std::size_t>(k)] - creases_at[static_cast<std::size_t>(k)]; };
          const bool bends_falling = track && track_bends && it / 2 >= 1 && hard(1) > creases_at[1] &&
                                     (bends_at[it] < fall * bends_at[it / 2] || (rules.points_hard_floor && hard(it) > crease_limit));
          const bool falling = (soft_falling || bends_falling) && !(while_falling && fall_off) &&
                               (while_falling || creases_at[it] > fall_floor);
          if (falling && ran_past_target == 0) {
            ran_past_target = it;
            past_target_by_bends = !soft_falling;
          }
          if (!falling) {
            reached = true;
            if ((!plateau && !floor_rule) || (ends_at_target && ends_at_target(accepted, last_pass))) return false;
            if (floor_rule && it < rules.flat_floor_iterations && bend_share(at, topo, -1.0, rules.flat_max_deg) >= rules.flat_floor_share)
              floor_at = rules.flat_floor_iterations;
            if (!plateau && floor_at == 0) return false;
            target_it = it;
            at_target = Snapshot{accepted, last_pass, last_turned, last_volume_change, volume_failed};
            return true;
          }
        }
      }
      return true;
    }, &cache);
    // The run ended (iteration cap, result check) before plateau_end or the floor: decided on what it
    // reached. Past the floor, the floor's iteration is kept.
    if (target_it > 0 && target_on && !revert) {
      const int last = static_cast<int>(moved.size()) - 1;
      if (plateau && !plateau_judged && !floored && last > target_it && levelled(last)) levelled_at = target_it;
      else if (floor_at > 0) floored = true;
      else revert = true;
    }
    // Back to what the run kept at iteration `it` (`snap`).
    auto restore = [&](Snapshot& snap, int it) {
      accepted = std::move(snap.accepted);
      last_pass = snap.last_pass;
      last_turned = snap.last_turned;
      last_volume_change = snap.last_volume_change;
      volume_failed = snap.volume_failed;
      rep.iterations = it;
    };
    if (floored && rep.iterations > floor_at) restore(at_floor, floor_at);
    if (floored) {
      reached = false;
      flat_floor_from = target_it;
      flat_floor_to = std::min(floor_at, rep.iterations);  // (the result check may have ended the run before)
      // (the floor is moved before flat_floor_iterations only by the growth limit)
      flat_floor_grown = floor_at < rules.flat_floor_iterations && flat_floor_to == floor_at;
      rep.stop_reason = "iterations";
    }
    if (revert) {
      restore(at_target, target_it);
    } else if (levelled_at > 0) {
      reached = false;
    }
    if (last_pass < rep.iterations) {
      if (volume_failed)
        std::snprintf(line, sizeof line, "the last %d iterations changed the volume by more than %.2f%% (the last: %.2f%%); iteration %d kept",
                      rep.iterations - last_pass, 100.0 * rules.max_volume_change, 100.0 * last_volume_change, last_pass);
      else
        std::snprintf(line, sizeof line,
                      "the last %d iterations turned %.2f%% of the surface against the smoothed input (input: %.2f%%); iteration %d kept",
                      rep.iterations - last_pass, 100.0 * last_turned, 100.0 * input_turned, last_pass);
      verdict = line;
      rep.iterations = last_pass + 1;  // (one is taken off below)
    }
    m.positions = accepted;  // the last iteration that passed (denoise's own result otherwise)
    refresh_stored_normals(m);
    if (verdict != "passed") {
      rep.iterations = std::max(0, rep.iterations - 1);
      rep.stop_reason = "result check";
    } else if (reached) {
      rep.stop_reason = "target displacement";
    }
    rep.displacement = normal_displacement(topo, m.faces, start, m.positions);
    return std::make_pair(rep, verdict);
  };

  // Step 6: folds the run left, unfolded where that turns no more of the surface against the reference.
  auto unfold = [&](Mesh& m) {
    // The input returned as it was is left as it is, unless it is a triangulation of scanned points, whose
    // own folds are defects the run did not have to make.
    if (r.run.iterations == 0 && !o.scanned) return;
    add_vertex_vertices(topo);  // (released during the runs)
    add_face_faces(topo, m.num_faces());
    // Folds the noise made and the run left are folds too; the result check keeps the raw reference,
    // against which its constants were fitted.
    const std::vector<Vec3> unfold_reference = fold_reference(reference, m.faces, topo, geometry_of(input).areas);
    std::vector<Vec3> pos = m.positions;
    // A scanned mesh's slivers are its triangulation's, and a fold there is a defect like any other.
    r.unfold = unfold_faces(pos, m.faces, topo, input, unfold_reference, 10, 0.5, o.scanned);
    if (r.unfold.moved == 0) return;
    FaceGeometry before, after;
    compute_face_geometry(m.positions, m.faces, before);
    compute_face_geometry(pos, m.faces, after);
    if (turned_area_share(after, unfold_reference) > turned_area_share(before, unfold_reference)) {
      r.unfold.remaining = r.unfold.folds;
      r.unfold.moved = 0;
      return;
    }
    m.positions = std::move(pos);
    refresh_stored_normals(m);
  };

  // How far the result moved the surface as a whole (AutoRules::shift_warning).
  auto measure_shift = [&](const Mesh& m) {
    FaceGeometry g;
    compute_face_geometry(m.positions, m.faces, g, false);
    r.mean_normal_move = mean_normal_move(topo, g, input, m.positions);
    r.volume_change = closed && std::abs(input_volume) > 0.0 ? (enclosed_volume(m.positions, m.faces) - input_volume) / std::abs(input_volume) : 0.0;
    r.shifted = rules.shift_warning > 0.0 && std::abs(r.mean_normal_move) > std::max(rules.shift_warning * r.noise, rules.shift_warning_edges * edge);
  };

  if (!has_area) {
    // No face has an area, so no face has a normal to filter: a run would leave every vertex where it is.
    r.mode = "untouched";
    r.reason = "every face has zero area (no face normal to filter): nothing to denoise";
    r.options.iterations = 0;
    r.check = "not needed";
    return r;
  }
  if (rules.clean_agreement > 0.0 && na.height_agreement >= rules.clean_agreement && !o.scanned && !is_given("iterations")) {
    // Curvature makes neighbours' heights alike, noise makes them unrelated: a coarse smooth model's own
    // shape read as noise would only be smoothed away (the clean spot, 1.98 degrees from itself after a run).
    // Not a mesh made from scanned points, which carry the scanner's noise however smooth the surface
    // looks: Poisson's meshes of sparse scans read above the limit, and leaving them as they came moved the
    // main job's results both ways (docs/EXPERIMENTS.md).
    r.mode = "untouched";
    std::snprintf(line, sizeof line,
                  "neighbouring vertices agree on their heights over their one-rings (%.2f, limit %.2f; noise leaves them "
                  "unrelated): a surface smooth at the scale of its edges, left as it is",
                  na.height_agreement, rules.clean_agreement);
    r.reason = line;
    r.options.iterations = 0;
    r.check = "not needed";
    return r;
  }
  // A mesh triangulated from scanned points has noise on every vertex (its cloud's isolated outliers were
  // removed before meshing): the isolated spikes it shows are its triangulation's slivers and folds, and
  // moving only them would leave the rest as noisy as it came (on single-view virtual scans of fandisk, noise
  // 0.2-0.3: 20.9 and 27.9 degrees from the clean surface against 4.2 and 7.6 for the regular run).
  const bool spikes = na.isolated_outlier_share > rules.impulsive_share;
  std::string scan_note;  // (prefixed to the reason the scanned mesh's run ends with)
  if (spikes && o.scanned) {
    std::snprintf(line, sizeof line, "%.1f%% of the vertices are isolated spikes, taken for the triangulation's slivers (a scanned mesh: every vertex is noisy); ",
                  100.0 * na.isolated_outlier_share);
    scan_note = line;
  } else if (spikes) {
    // Impulsive noise: a few vertices far off, the rest exact. Moving everyone would smooth away detail
    // the noise never touched; only the outliers move, towards the planes of their filtered normals.
    r.mode = "impulsive";
    if (!is_given("sigma_s")) o.sigma_s = rules.impulsive_sigma;
    if (!is_given("lambda")) o.lambda = rules.impulsive_lambda;
    if (!is_given("outlier_jump")) o.outlier_jump = rules.outlier_jump;
    if (!is_given("outlier_peaks")) o.outlier_peaks = rules.outlier_peaks;
    if (!is_given("iterations")) o.iterations = rules.impulsive_iterations;
    std::snprintf(line, sizeof line, "impulsive noise: %.1f%% of the vertices are isolated outliers; only those move",
                  100.0 * na.isolated_outlier_share);
    r.reason = line;
    auto [rep, verdict] = checked_run(mesh, o, {}, false);
    r.run = rep;
    r.check = verdict;
    r.options = o;
    unfold(mesh);
    measure_shift(mesh);
    return r;
  }

  if (na.exact_plane_fraction >= 0.1 && !is_given("iterations")) {
    // Scanner noise never leaves vertices exactly in their neighbours' plane; a CAD tessellation or an
    // already clean mesh does, and its (often sliver) triangles would only be disturbed.
    r.mode = "untouched";
    std::snprintf(line, sizeof line, "%.0f%% of the vertices lie exactly in the plane of their faces: noise-free, left as it is",
                  100.0 * na.exact_plane_fraction);
    r.reason = scan_note + line;
    r.options.iterations = 0;
    r.check = "not needed";
    return r;
  }

  // Feature-keeping run first; its state after the probe iterations tells whether the creases it keeps
  // are real (CAD parts, buildings) or noise it locked in (organic shapes).
  DenoiseOptions sharp = o, smooth = o;
  if (!is_given("sigma_s")) sharp.sigma_s = rules.sharp_sigma, smooth.sigma_s = rules.smooth_sigma;
  if (!is_given("lambda")) {
    sharp.lambda = rules.sharp_lambda, smooth.lambda = rules.smooth_lambda;
    if (o.vertices_are_points && rules.scanned_lambda_level > 0.0) {
      // A scan's triangulation under weak noise: evening out its triangles costs more than the noise. The
      // feature-keeping run keeps its weight: the sharp/smooth decision was fitted on its creases.
      const double x = std::min(1.0, na.level / rules.scanned_lambda_level);
      smooth.lambda *= x * x;
    }
  }
  sharp.iterations = smooth.iterations = cap;
  if (!is_given("target_displacement") && !is_given("iterations")) {
    sharp.target_displacement = rules.sharp_target * r.noise / edge;
    smooth.target_displacement = smooth_target_ratio(rules, na.level) * r.noise / edge;
  }
  const bool decide = !is_given("sigma_s");
  double creases = -1.0;
  bool clear = false;
  const bool flattening = rules.flat_growth_per_level > 0.0;
  double flat_half = -1.0, flat = -1.0;  // at half the probe and at the probe
  bool flattened = false;  // taken as smooth because its flat edges stopped growing
  auto probe = [&](int it, const FaceGeometry& g) {
    if (!decide) return Probe::go_on;
    if (flattening && it == rules.probe_iterations / 2 && it > 0) flat_half = bend_share(g, topo, -1.0, rules.flat_max_deg);
    if (it != rules.probe_iterations) return Probe::go_on;
    creases = bend_share(g, topo, rules.soft_crease_min_deg, rules.soft_crease_max_deg);
    if (creases > crease_limit) return Probe::stop;  // smooth shape: this run ends here
    if (flattening && flat_half >= 0.0) {
      flat = bend_share(g, topo, -1.0, rules.flat_max_deg);
      const double bends = bend_share(g, topo, rules.soft_crease_min_deg, 180.0);
      const double strong = bend_share(g, topo, rules.soft_crease_max_deg, 180.0);
      flattened = flat < rules.flat_share_max && flat - flat_half < rules.flat_growth_per_level * na.level && bends > rules.flat_min_bends &&
                  strong < rules.flat_max_strong;
      if (flattened) return Probe::stop;
      fall_off = flat < rules.crease_fall_min_flat;
    }
    // Clearly machined: flat faces keep improving long after the noise-sized displacement.
    clear = rules.clear_sharp_share > 0.0 && creases < rules.clear_sharp_share && !is_given("target_displacement");
    return clear ? Probe::no_target : Probe::go_on;
  };
  // A smooth shape's run needs the same connectivity again: on small meshes, where building it is a
  // noticeable share of --auto's time (spot, 5.8k faces: 1 of 22 ms), the probe run copies it instead of
  // taking it. Not on large ones, where the copy (~80 bytes a face, alive through the whole run) would
  // raise the peak (810k faces: 457 -> 523 MB) for a build that costs them a few percent.
  cache.keep_topology(mesh.num_faces() <= 100000);
  // Reached the target before the probe: decided there, on what the run keeps (as after a run that ends
  // at its target); a smooth shape ends the run. If it keeps the input (no iteration passed the result
  // check), there is nothing to judge: the input's creases are its noise, and a wider kernel would turn
  // more of the surface still. The input is returned (as the fit's replay of the grids scores it).
  bool nothing_at_target = false;  // the target came with the input kept
  auto smooth_at_target = [&](const std::vector<Vec3>& kept, int kept_iteration) {
    if (!decide || creases >= 0.0) return false;
    if (kept_iteration == 0) {
      nothing_at_target = true;
      return false;
    }
    creases = soft_crease_share(kept, mesh, topo, rules.soft_crease_min_deg, rules.soft_crease_max_deg);
    return creases > crease_limit;
  };
  auto [rep, verdict] = checked_run(mesh, sharp, probe, true, smooth_at_target);
  cache.keep_topology(false);
  // Ended before the probe (and not by the target, which smooth_at_target judged): decided on what it
  // keeps, unless that is the input (see smooth_at_target).
  if (decide && creases < 0.0 && !nothing_at_target && rep.iterations > 0)
    creases = soft_crease_share(mesh.positions, mesh, topo, rules.soft_crease_min_deg, rules.soft_crease_max_deg);
  const bool nothing_kept = decide && creases < 0.0;
  r.crease_share = creases;
  r.flat_share = flat;
  r.flat_share_half = flat_half;
  // On a triangulation of scanned points nothing kept is no verdict on the shape: its vertices are all
  // noisy points, and the narrow kernel snaps its irregular triangles to one side or the other of the
  // creases it keeps, which the check sees as turned surface. The wide kernel's run is tried instead
  // (checked the same way, so a run that turns the surface still returns the input). Not on other meshes:
  // there a clean-looking input under weak noise is better kept as it is (the corpus's beetle, Gaussian
  // 0.1: 17.50 degrees as it came, 19.82 after the wide kernel's checked run).
  const bool scan_fallback = decide && nothing_kept && o.vertices_are_points;
  if (decide && (creases > crease_limit || flattened || scan_fallback)) {
    r.mode = "smooth";
    if (scan_fallback)
      std::snprintf(line, sizeof line,
                    "no feature-keeping iteration passed the result check before the %s (it turned more of the surface than the "
                    "noise did); a triangulation of scanned points: the wide kernel instead",
                    nothing_at_target ? "displacement target" : "probe");
    else if (flattened)
      std::snprintf(line, sizeof line,
                    "smooth shape: after %d feature-keeping iteration%s only %.0f%% of the edges are flat (within %.0f deg), "
                    "%.1f points more than at %d: a curved surface the narrow kernel cuts into facets",
                    rep.iterations, plural(rep.iterations), 100.0 * flat, rules.flat_max_deg, 100.0 * (flat - flat_half), rules.probe_iterations / 2);
    else
      std::snprintf(line, sizeof line,
                    "smooth shape: after %d feature-keeping iteration%s %.1f%% of the edges are still soft creases (%.0f-%.0f deg; "
                    "limit %.1f%%): noise the narrow kernel locked in",
                    rep.iterations, plural(rep.iterations), 100.0 * creases, rules.soft_crease_min_deg, rules.soft_crease_max_deg, 100.0 * crease_limit);
    r.reason = line;
    r.probe_iterations = rep.iterations;
    ran_past_target = 0;  // (the feature-keeping run's, if it went past its target before the probe)
    mesh.positions = input;  // the wide kernel's run starts from the input too
    refresh_stored_normals(mesh);
    auto [rep2, verdict2] = checked_run(mesh, smooth, {}, false, {}, rules.smooth_crease_fall);
    if (ran_past_target > 0) {
      if (past_target_by_bends)
        std::snprintf(line, sizeof line,
                      " while its creases were still falling fast or many edges still bent over %.0f deg (noise wider than the "
                      "point spacing: after its first iteration more edges bent over that than %.0f-%.0f deg)",
                      rules.soft_crease_max_deg, rules.soft_crease_min_deg, rules.soft_crease_max_deg);
      r.reason += "; the wide kernel went on past the displacement target at iteration " + std::to_string(ran_past_target) +
                  (past_target_by_bends ? line : " while its soft creases were still falling fast");
    }
    r.ran_past_target = ran_past_target;
    r.run = rep2;
    r.check = verdict2;
    r.options = smooth;
    unfold(mesh);
  } else {
    r.mode = "sharp";
    if (nothing_kept)
      std::snprintf(line, sizeof line,
                    "not judged: no feature-keeping iteration passed the result check before the %s (denoising turns more "
                    "of the surface than the noise did; the input's creases are its noise); the feature-keeping run kept %d iteration%s",
                    nothing_at_target ? "displacement target" : "probe", rep.iterations, plural(rep.iterations));
    else if (decide)
      std::snprintf(line, sizeof line, "sharp features: after %d feature-keeping iteration%s only %.1f%% of the edges are soft creases%s%s%s",
                    std::min(rep.iterations, rules.probe_iterations), plural(std::min(rep.iterations, rules.probe_iterations)), 100.0 * creases,
                    ran_past_target > 0 ? ("; went on past the displacement target at iteration " + std::to_string(ran_past_target) +
                                           " while its soft creases were still falling fast").c_str()
                                        : "",
                    flat_floor_from > 0 ? ("; reached the displacement target at iteration " + std::to_string(flat_floor_from) +
                                           " with at least " + std::to_string(static_cast<int>(std::lround(100.0 * rules.flat_floor_share))) +
                                           "% of the edges flat, and went on to iteration " + std::to_string(flat_floor_to) +
                                           (flat_floor_grown
                                                ? " (where its displacement had grown by more than " +
                                                      std::to_string(static_cast<int>(std::lround(100.0 * rules.flat_floor_growth))) +
                                                      "% past the target's)"
                                                : std::string()))
                                              .c_str()
                                        : "",
                    clear             ? " (clearly machined: no displacement stop)"
                    : levelled_at > 0 ? "; the displacement levelled off after the target (no displacement stop)"
                                      : "");
    else
      std::snprintf(line, sizeof line, "sigma_s given: one run%s",
                    levelled_at > 0 ? "; the displacement levelled off after the target (no displacement stop)" : "");
    r.reason = line;
    r.levelled_at = levelled_at;
    r.ran_past_target = ran_past_target;
    r.flat_floor_from = flat_floor_from;
    r.flat_floor_to = flat_floor_to;
    r.run = rep;
    r.check = verdict;
    r.options = sharp;
    unfold(mesh);
  }
  r.reason = scan_note + r.reason;
  measure_shift(mesh);
  return r;
}

}  // namespace scanmesh
