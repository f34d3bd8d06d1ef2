// Choosing the meshing method by measuring what each makes of the cloud.
#include "scanmesh/mesh_cloud.h"

#include <chrono>
#include <cstdio>

#include "scanmesh/clean_cloud.h"
#include "scanmesh/clean_mesh.h"
#include "scanmesh/errors.h"

namespace scanmesh {
namespace {

// How far a mesh falls short of representing the points: percentage points of coverage below the limit,
// plus one for every hole the limits count. 0 = nothing wrong.
double shortfall(const ScanFit& fit, const ScanFitLimits& limits) {
  double s = std::max(0.0, limits.min_coverage - fit.coverage) * 100.0;
  for (const auto& l : fit.loops)
    s += l.kind == BoundaryLoopFit::Kind::hole && l.perimeter >= limits.min_hole_perimeter * fit.spacing ? 1.0 : 0.0;
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
  std::size_t big = 0;
  for (const auto& l : f.loops) big += l.kind == BoundaryLoopFit::Kind::hole && l.perimeter >= limits.min_hole_perimeter * f.spacing ? 1 : 0;
  char b[160];
  std::snprintf(b, sizeof b, "covers %.1f%% of the points, %zu hole%s", 100.0 * f.coverage, big, big == 1 ? "" : "s");
  return b;
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
    switch (m) {
      case MeshMethod::organized: return triangulate_organized(cloud, organized, scale);
      case MeshMethod::poisson: return triangulate_poisson(cloud, poisson, scale);
      default: return triangulate_gp3(cloud, gp3, scale);
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
  Mesh g = triangulate_gp3(cloud, gp3, scale);
  clean_mesh(g, CleanupOptions{}, cloud.sensor_origin);
  ScanFit gf = measure_scan_fit(g, points, scale.spacing);
  const double gs = shortfall(gf, limits);
  say("greedy projection: " + std::to_string(g.faces.size()) + " faces, " + fit_words(gf, limits));
  d.numbers = {{"gp3_coverage", gf.coverage}, {"gp3_holes", static_cast<double>(gf.holes)}, {"gp3_pieces", static_cast<double>(gf.pieces)}};
  if (gs == 0.0) {
    d.method = MeshMethod::gp3;
    d.reason = "unorganized cloud: greedy projection " + fit_words(gf, limits);
    d.fit = std::move(gf);
    return g;
  }
  // An implicit surface needs samples to be fitted to: below a hundred points Poisson only invents a blob.
  constexpr std::size_t kMinPoissonPoints = 100;
  if (points.size() < kMinPoissonPoints) {
    d.method = MeshMethod::gp3;
    d.reason = "greedy projection " + fit_words(gf, limits) + "; too few points (" + std::to_string(points.size()) +
               ") for Poisson: greedy projection";
    d.fit = std::move(gf);
    return g;
  }
  PoissonOptions chosen = poisson;  // the depth from the spacing, computed once (a pass over the points)
  if (chosen.depth <= 0) chosen.depth = poisson_depth_for(cloud, scale);
  const int depth = chosen.depth;
  say("it falls short: screened Poisson, depth " + std::to_string(depth));
  Mesh p;
  try {
    p = triangulate_poisson(cloud, chosen, scale);
    clean_mesh(p, CleanupOptions{}, cloud.sensor_origin);
  } catch (const InputError&) {
    p = Mesh{};
  }
  ScanFit pf = measure_scan_fit(p, points, scale.spacing);
  say("screened Poisson: " + std::to_string(p.faces.size()) + " faces" + (p.faces.empty() ? std::string() : ", " + fit_words(pf, limits)));
  const double ps = p.faces.empty() ? 1e300 : shortfall(pf, limits);
  d.numbers.insert(d.numbers.end(), {{"poisson_coverage", pf.coverage},
                                     {"poisson_holes", static_cast<double>(pf.holes)},
                                     {"poisson_pieces", static_cast<double>(pf.pieces)},
                                     {"poisson_depth", static_cast<double>(depth)}});
  // The smaller shortfall wins; on a tie greedy projection, which keeps the measured points.
  if (ps < gs) {
    d.method = MeshMethod::poisson;
    d.reason = "greedy projection " + fit_words(gf, limits) + "; screened Poisson (trimmed) " + fit_words(pf, limits) + ": Poisson";
    d.fit = std::move(pf);
    return p;
  }
  d.method = MeshMethod::gp3;
  d.reason = "greedy projection " + fit_words(gf, limits) + "; screened Poisson (trimmed) " +
             (p.faces.empty() ? std::string("made nothing") : fit_words(pf, limits)) + ": greedy projection";
  d.fit = std::move(gf);
  return g;
}

}  // namespace scanmesh
