// Choosing the meshing method by measuring what each makes of the cloud.
#include "scanmesh/mesh_cloud.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <unordered_set>

#include "scanmesh/clean_cloud.h"
#include "scanmesh/clean_mesh.h"
#include "scanmesh/errors.h"
#include "scanmesh/fill_holes.h"
#include "scanmesh/flip_edges.h"
#include "scanmesh/heartbeat.h"
#include "scanmesh/neighbourhoods.h"

namespace scanmesh {
namespace {

// The loops mesh.auto holds against a mesh and closes: holes (points left out inside) and gaps with
// covered points beside them off the mesh (see BoundaryLoopFit::points_beside).
bool open_loop(const BoundaryLoopFit& l) {
  return l.kind == BoundaryLoopFit::Kind::hole || (l.kind == BoundaryLoopFit::Kind::gap && l.points_beside);
}

// An open loop long enough for the limits to count it.
bool held_open(const BoundaryLoopFit& l, double spacing, const ScanFitLimits& limits) {
  return open_loop(l) && l.perimeter >= limits.min_hole_perimeter * spacing;
}

// How far a mesh falls short of representing the points: percentage points of coverage below the limit
// and of faces lying over other pieces above theirs, plus one for every loop held open (with `gaps_count`
// false, holes only). 0 = nothing wrong.
double shortfall(const ScanFit& fit, const ScanFitLimits& limits, bool gaps_count = true) {
  double s = std::max(0.0, limits.min_coverage - fit.coverage) * 100.0;
  s += std::max(0.0, fit.layered_share - limits.max_layered_share) * 100.0;
  for (const auto& l : fit.loops)
    s += held_open(l, fit.spacing, limits) && (gaps_count || l.kind == BoundaryLoopFit::Kind::hole) ? 1.0 : 0.0;
  return s;
}

std::vector<Vec3> finite_points(const PointCloud& cloud) {
  std::vector<Vec3> out;
  out.reserve(cloud.size());
  for (const Vec3& p : cloud.points)
    if (p.allFinite()) out.push_back(p);
  return out;
}

std::string fit_words(const ScanFit& f, const ScanFitLimits& limits) {
  std::size_t holes = 0, beside = 0;
  for (const auto& l : f.loops)
    if (held_open(l, f.spacing, limits)) (l.kind == BoundaryLoopFit::Kind::hole ? holes : beside) += 1;
  char b[160];
  std::snprintf(b, sizeof b, "covers %.1f%% of the points, %zu hole%s", 100.0 * f.coverage, holes, holes == 1 ? "" : "s");
  std::string out = b;
  if (beside > 0) out += " and " + std::to_string(beside) + " gap" + (beside == 1 ? "" : "s") + " with points beside";
  if (f.layered_share > limits.max_layered_share) {
    std::snprintf(b, sizeof b, ", %.1f%% of its faces in pieces lying over others", 100.0 * f.layered_share);
    out += b;
  }
  return out;
}

// A cloud at least this share of whose normals lie in one hemisphere is one-sided: a single view (from its
// sensor every visible surface faces it), or an open surface such as a relief or a bowl (the sidecar's
// one_sided_normals; the stage's line says so when it keeps greedy projection's gaps open). Virtual scans of five models (scanmesh scan, 96 x
// 72 and 320 x 240 pixels): one view 1.00, two views 0.66-0.80, three to eight 0.53-0.69; the real
// single-view clouds of ../shared/data/clouds 0.96-1.00, the complete kitten 0.54.
constexpr double kOneSidedShare = 0.9;

// The largest share of the cloud's normals within 90 degrees of one direction, over their mean direction
// and 256 directions spread evenly over the sphere (0 without normals). At most 20,000 normals are looked at,
// evenly through the cloud.
double one_sided_share(const PointCloud& cloud) {
  if (!cloud.has_normals()) return 0.0;
  std::vector<Vec3> normals;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (cloud.points[i].allFinite() && cloud.normals[i].allFinite() && cloud.normals[i].squaredNorm() > 0.0) normals.push_back(cloud.normals[i]);
  if (normals.empty()) return 0.0;
  std::vector<Vec3> directions;
  Vec3 sum = Vec3::Zero();
  for (const Vec3& n : normals) sum += n;
  if (sum.norm() > 0.0) directions.push_back(sum.normalized());
  const std::size_t stride = (normals.size() + 19999) / 20000;
  std::vector<Vec3> sample;
  for (std::size_t i = 0; i < normals.size(); i += stride) sample.push_back(normals[i]);
  constexpr int kDirections = 256;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < kDirections; ++k) {
    const double z = 1.0 - 2.0 * (k + 0.5) / kDirections, r = std::sqrt(1.0 - z * z);
    directions.emplace_back(r * std::cos(golden * k), r * std::sin(golden * k), z);
  }
  std::size_t best = 0;
  for (const Vec3& d : directions)
    best = std::max(best, static_cast<std::size_t>(std::count_if(sample.begin(), sample.end(), [&d](const Vec3& n) { return n.dot(d) > 0.0; })));
  return static_cast<double>(best) / static_cast<double>(sample.size());
}

// Above this share of points with opposed normals, mesh.auto also tries Poisson on propagated normals.
// The virtual scans (4 views) of train/'s models: closed ones 0.02-0.09, open sheets and the beetle's
// shell 0.78-0.85; real clouds reaching this step (hippo1) 0.
constexpr double kOpposedShare = 0.3;

// Share of the points with a neighbour within 1.5 spacings whose normal points the other way
// (n_i . n_j < -0.5): a sheet seen from both sides, each view's normals facing its own sensor, or parts
// thinner than the point spacing. Poisson wraps such points into two layers.
double opposed_normal_share(const PointCloud& cloud, double spacing) {
  if (!cloud.has_normals() || !(spacing > 0.0)) return 0.0;
  std::vector<Vec3> points, normals;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (cloud.points[i].allFinite() && cloud.normals[i].allFinite() && cloud.normals[i].squaredNorm() > 0.0) {
      points.push_back(cloud.points[i]);
      normals.push_back(cloud.normals[i].normalized());
    }
  if (points.size() < 2) return 0.0;
  const Adjacency near = radius_neighbourhoods(points, 1.5 * spacing, 16);
  std::size_t opposed = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    for (const int* j = near.begin(i); j != near.end(i); ++j)
      if (normals[i].dot(normals[*j]) < -0.5) {
        ++opposed;
        break;
      }
  return static_cast<double>(opposed) / static_cast<double>(points.size());
}

// Closes every loop but the pieces' rims: the loops held open (points inside left out, or beside them: a
// meshing failure; loops too short to count as well), and gaps, where a patch may still lie on the data.
// A patch stays only where it lies on the data: every one of its faces' centroids within `trim` of an
// input point (MeshMethodOptions::fill_trim), so a gap the scan saw nothing of stays open. Gaps are
// closed too because the boundary between a gap and a hole is a matter of a spacing: a small loop whose
// inside has points near some probes and not others is a gap, and denoising, which moves the loop by a
// fraction of a spacing, can make it a hole in the final mesh (a virtual scan of the cow, 6 views of
// 160 x 120, noise 0.4: greedy projection with a 14-spacing gap, status degraded after denoising).
// A hole encloses measured surface, so its patch may reach `hole_trim` (>= trim) from the points. With
// `holes_only`, only the holes are closed. Returns the number of loops closed.
std::size_t fill_scan_holes(Mesh& mesh, const ScanFit& fit, const std::vector<Vec3>& points, double trim, double hole_trim,
                            bool holes_only = false) {
  std::vector<std::vector<int>> rings;
  std::unordered_set<int> on_hole;  // the vertices of the holes' loops
  for (const auto& l : fit.loops) {
    if (holes_only ? l.kind == BoundaryLoopFit::Kind::hole : l.kind != BoundaryLoopFit::Kind::rim) rings.push_back(l.ring);
    if (l.kind == BoundaryLoopFit::Kind::hole) on_hole.insert(l.ring.begin(), l.ring.end());
  }
  if (rings.empty()) return 0;
  std::size_t zipped = 0;
  rings = zip_slits(mesh, rings, &zipped);  // loops zipped shut are gone, others keep their vertices but the welded ones
  std::vector<double> ring_trim(rings.size(), trim);
  for (std::size_t i = 0; i < rings.size(); ++i)
    if (!rings[i].empty() && on_hole.count(rings[i].front()) > 0) ring_trim[i] = hole_trim;
  std::vector<FilledHole> patches = fill_holes(mesh, rings);
  std::vector<Vec3> centroids;
  std::vector<std::size_t> owner;
  for (std::size_t i = 0; i < patches.size(); ++i)
    for (std::size_t f = patches[i].first_face; f < patches[i].first_face + patches[i].faces; ++f) {
      const Face& t = mesh.faces[f];
      centroids.push_back((mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0);
      owner.push_back(i);
    }
  const std::vector<double> d = nearest_point_distances(points, centroids);
  std::vector<char> keep(patches.size(), 0);
  for (std::size_t i = 0; i < patches.size(); ++i) keep[i] = patches[i].filled ? 1 : 0;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (!(d[k] <= ring_trim[owner[k]])) keep[owner[k]] = 0;
  remove_patches(mesh, patches, keep);
  return zipped + static_cast<std::size_t>(std::count(keep.begin(), keep.end(), 1));
}

}  // namespace

const char* method_name(MeshMethod method) {
  switch (method) {
    case MeshMethod::gp3: return "gp3";
    case MeshMethod::organized: return "organized";
    case MeshMethod::poisson: return "poisson";
    default: return "auto";
  }
}

Mesh mesh_cloud(PointCloud& cloud, const MeshMethodOptions& method, const Gp3Options& gp3, const OrganizedOptions& organized,
                const PoissonOptions& poisson, const CloudScale& scale, MeshingDecision* decision,
                const std::function<void(const std::string&)>& note) {
  MeshingDecision local;
  MeshingDecision& d = decision ? *decision : local;
  MeshMethod m = method.method;
  if (const std::string problem = surface_problem(cloud); !problem.empty())
    throw InputError("meshing: " + problem + ": there is no surface to mesh");
  if (m == MeshMethod::organized && !cloud.organized())
    throw InputError("organized meshing needs an organized cloud (a width x height grid); this one is a list of " +
                     std::to_string(cloud.size()) + " points (use method gp3 or poisson)");
  if (m == MeshMethod::automatic && cloud.organized()) {
    d.method = MeshMethod::organized;
    d.reason = "organized cloud (" + std::to_string(cloud.width) + " x " + std::to_string(cloud.height) + " grid): organized meshing";
    return triangulate_organized(cloud, organized, scale);
  }
  if (m != MeshMethod::organized && !cloud.has_normals()) estimate_normals(cloud, NormalOptions{});
  if (m != MeshMethod::automatic) {
    d.method = m;
    d.reason = std::string("method ") + method_name(m) + " as configured";
    const Heartbeat beat(kHeartbeatSeconds, [&note, m](double seconds) {
      if (!note) return;
      char b[96];
      std::snprintf(b, sizeof b, "%s: still running (%.0f s)", method_name(m), seconds);
      note(b);
    });
    switch (m) {
      case MeshMethod::organized: return triangulate_organized(cloud, organized, scale);
      case MeshMethod::poisson: return triangulate_poisson(cloud, poisson, scale);
      default: {
        Mesh g = triangulate_gp3(cloud, gp3, scale);
        if (gp3.flips) flip_edges(g);
        return g;
      }
    }
  }

  // Unorganized: greedy projection first; Poisson only when greedy projection falls short. Each candidate
  // is measured as the clean-up stage would leave it (folds and non-manifold pieces removed, oriented).
  const ScanFitLimits limits;
  const std::vector<Vec3> points = finite_points(cloud);
  auto t0 = std::chrono::steady_clock::now();
  auto say = [&](const std::string& line) {
    if (!note) return;
    char b[32];
    std::snprintf(b, sizeof b, " (%.1f s)", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    note(line + b);
  };
  say("greedy projection of " + std::to_string(points.size()) + " points");
  // PCL's greedy projection and Poisson report nothing while they run (minutes on large clouds).
  auto still_running = [&](const char* step) {
    return [&say, step](double) { say(std::string(step) + ": still running"); };
  };
  Mesh g;
  {
    const Heartbeat beat(kHeartbeatSeconds, still_running("greedy projection"));
    g = triangulate_gp3(cloud, gp3, scale);
  }
  clean_mesh(g, CleanupOptions{}, cloud.sensor_origin);
  std::string flipped;
  if (gp3.flips) {
    const FlipReport fr = flip_edges(g);
    flipped = ", " + std::to_string(fr.flips) + " edges flipped towards Delaunay";
  }
  ScanFit gf = measure_scan_fit(g, points, scale.spacing);
  say("greedy projection: " + std::to_string(g.faces.size()) + " faces" + flipped + ", " + fit_words(gf, limits));
  // Both sides of a thin sheet or an open shell seen (each view's normals facing its own sensor): greedy
  // projection meshes each side's points as a layer of its own, pieces lying over one another. The
  // largest layer is kept and the pieces over it removed; what they alone covered counts as left out.
  std::size_t peeled = 0;
  if (gf.layered_share > limits.max_layered_share) {
    peeled = gf.layered_pieces;
    std::size_t kept = 0;
    for (std::size_t f = 0; f < g.faces.size(); ++f)
      if (!gf.layered_faces[f]) g.faces[kept++] = g.faces[f];
    g.faces.resize(kept);
    clean_mesh(g, CleanupOptions{}, cloud.sensor_origin);
    gf = measure_scan_fit(g, points, scale.spacing);
    say("greedy projection, " + std::to_string(peeled) + " pieces lying over others removed: " + std::to_string(g.faces.size()) + " faces, " +
        fit_words(gf, limits));
  }
  const double one_sided = one_sided_share(cloud);
  const bool one_sided_surface = one_sided >= kOneSidedShare;
  std::size_t closed_holes = 0;
  const bool closing_ran = method.fill_holes && (shortfall(gf, limits) > 0.0 || gf.gaps > 0);
  const double trim = (one_sided_surface ? method.fill_trim_one_sided : method.fill_trim).resolve(scale.spacing, scale.spacing, scale.diagonal);
  if (closing_ran) {
    // A hole encloses measured surface, so its patch may reach as far from the points as trimmed
    // Poisson's surface does (a virtual scan of featuretype, 8 views of 96 x 72: at the gaps' trim a
    // hole stayed open and sent the cloud to Poisson).
    const double hole_trim = std::max(trim, poisson.trim_distance.resolve(scale.spacing, scale.spacing, scale.diagonal));
    closed_holes = fill_scan_holes(g, gf, points, trim, hole_trim);
    // Closing can leave holes of its own: a patch that meets another loop at a vertex pinches it into a
    // long loop and a short one, too small to be a gap in the data (a virtual scan of the dragon, 12 views
    // of 1600 x 1200 thinned to 289k points: one such hole sent the cloud to Poisson, 31 s more). Up to
    // two more passes close the holes that count against the mesh.
    for (int pass = 0; pass < 3 && closed_holes > 0; ++pass) {
      clean_mesh(g, CleanupOptions{}, cloud.sensor_origin);
      gf = measure_scan_fit(g, points, scale.spacing);
      say("greedy projection, " + std::to_string(closed_holes) + " holes closed: " + std::to_string(g.faces.size()) + " faces, " + fit_words(gf, limits));
      if (pass == 2 || shortfall(gf, limits, false) == 0.0) break;
      const std::size_t more = fill_scan_holes(g, gf, points, hole_trim, hole_trim, true);
      if (more == 0) break;
      closed_holes += more;
    }
  }
  // A gap the closing left open would have needed a patch farther than the trim distance from every
  // point: a region no view saw (behind an occluding edge, or between the views of a complete object), where
  // no measured surface lies whatever points lie beside it, so it does not count against greedy projection.
  // Its rim runs through the points, so noise just inside it reads as "points beside"; trimmed Poisson
  // reaches up to the trim distance past the outermost points, and its loops have none beside them. Until
  // 2026-12-07 such gaps counted on all but one-sided clouds (a single view, an open relief or bowl), and
  // Poisson won around complete objects: on virtual scans of 11 models at five settings, 43 of 55 went to
  // Poisson, 31 of them only for such gaps, and greedy projection there had the lower E_v on 28 and the
  // lower normal error on 18 (means 2.25e-3 -> 1.58e-3 of the diagonal, 9.46 -> 9.01 degrees;
  // docs/EXPERIMENTS.md, "A scan's triangulation that no feature-keeping iteration improves").
  const double gs = shortfall(gf, limits, !closing_ran);
  std::string gp3_words = "greedy projection";
  if (peeled > 0 || closed_holes > 0) {
    gp3_words += " (";
    if (peeled > 0) gp3_words += std::to_string(peeled) + " piece" + (peeled == 1 ? "" : "s") + " lying over others removed";
    if (peeled > 0 && closed_holes > 0) gp3_words += ", ";
    if (closed_holes > 0) gp3_words += std::to_string(closed_holes) + " holes closed";
    gp3_words += ")";
  }
  d.numbers = {{"one_sided_normals", one_sided},
               {"gp3_coverage", gf.coverage},
               {"gp3_holes", static_cast<double>(gf.holes)},
               {"gp3_pieces", static_cast<double>(gf.pieces)},
               {"gp3_holes_closed", static_cast<double>(closed_holes)},
               {"gp3_fill_trim", closing_ran ? trim : 0.0},  // scene units; 0: the closing did not run
               {"gp3_layers_removed", static_cast<double>(peeled)}};
  if (gs == 0.0) {
    d.method = MeshMethod::gp3;
    d.reason = "unorganized cloud: " + gp3_words + " " + fit_words(gf, limits);
    if (closing_ran && gf.gaps > 0)
      d.reason += one_sided_surface ? " (one-sided, as a single view: the gaps left open are regions no view saw)"
                                    : " (the gaps left open lie farther than the trim distance from the points: regions no view saw)";
    d.fit = std::move(gf);
    return g;
  }
  // An implicit surface needs samples to be fitted to: below a hundred points Poisson only invents a blob.
  constexpr std::size_t kMinPoissonPoints = 100;
  if (points.size() < kMinPoissonPoints) {
    d.method = MeshMethod::gp3;
    d.reason = gp3_words + " " + fit_words(gf, limits) + "; too few points (" + std::to_string(points.size()) +
               ") for Poisson: greedy projection";
    d.fit = std::move(gf);
    return g;
  }
  bool propagated_normals = false;
  PoissonOptions chosen = poisson;  // the depth from the spacing, computed once (a pass over the points)
  if (chosen.depth <= 0) chosen.depth = poisson_depth_for(cloud, scale);
  const int depth = chosen.depth;
  say("it falls short: screened Poisson, depth " + std::to_string(depth));
  auto poisson_of = [&](const PointCloud& c) {
    Mesh out;
    try {
      {
        const Heartbeat beat(kHeartbeatSeconds, still_running("screened Poisson"));
        out = triangulate_poisson(c, chosen, scale);
      }
      clean_mesh(out, CleanupOptions{}, cloud.sensor_origin);
    } catch (const InputError&) {
      out = Mesh{};
    }
    return out;
  };
  Mesh p = poisson_of(cloud);
  ScanFit pf = measure_scan_fit(p, points, scale.spacing);
  // Normals that face each view's sensor point opposite ways on the two sides of a sheet seen from both
  // sides (or of a part thinner than the spacing), and Poisson then wraps the sheet in two layers, each
  // off the points. Where many points have such a neighbour, Poisson also runs on normals propagated
  // consistently from point to point, and the surface closer to the points is kept (a thin wall's two
  // real sides stay with the sensor's normals).
  const double opposed = opposed_normal_share(cloud, scale.spacing);
  d.numbers.push_back({"opposed_normals", opposed});
  if (opposed > kOpposedShare && !p.faces.empty()) {
    PointCloud propagated = cloud;
    propagated.normals.clear();
    propagated.sensor_origin.reset();
    estimate_normals(propagated, NormalOptions{});
    Mesh q = poisson_of(propagated);
    ScanFit qf = measure_scan_fit(q, points, scale.spacing);
    char b[256];
    std::snprintf(b, sizeof b, "%.0f%% of the points have a neighbour with opposite normal: Poisson on propagated normals, %.3g (sensor's: %.3g) mean distance to the points",
                  100.0 * opposed, qf.distance_mean, pf.distance_mean);
    say(b);
    if (!q.faces.empty() && qf.distance_mean < pf.distance_mean) {
      p = std::move(q);
      pf = std::move(qf);
      propagated_normals = true;
    }
  }
  say("screened Poisson: " + std::to_string(p.faces.size()) + " faces" + (p.faces.empty() ? std::string() : ", " + fit_words(pf, limits)));
  const double ps = p.faces.empty() ? 1e300 : shortfall(pf, limits);
  d.numbers.insert(d.numbers.end(), {{"poisson_coverage", pf.coverage},
                                     {"poisson_holes", static_cast<double>(pf.holes)},
                                     {"poisson_pieces", static_cast<double>(pf.pieces)},
                                     {"poisson_depth", static_cast<double>(depth)}});
  // The smaller shortfall wins; on a tie greedy projection, which keeps the measured points.
  if (ps < gs) {
    d.method = MeshMethod::poisson;
    d.reason = gp3_words + " " + fit_words(gf, limits) + "; screened Poisson (trimmed" +
               (propagated_normals ? ", normals propagated: the sensor's face opposite ways on a sheet" : "") + ") " + fit_words(pf, limits) + ": Poisson";
    d.fit = std::move(pf);
    return p;
  }
  d.method = MeshMethod::gp3;
  d.reason = gp3_words + " " + fit_words(gf, limits) + "; screened Poisson (trimmed) " +
             (p.faces.empty() ? std::string("made nothing") : fit_words(pf, limits)) + ": greedy projection";
  d.fit = std::move(gf);
  return g;
}

}  // namespace scanmesh
