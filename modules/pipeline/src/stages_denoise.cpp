// mesh.denoise and mesh.noise.
#include <algorithm>
#include <cstdio>
#include <utility>

#include "scanmesh/add_noise.h"
#include "scanmesh/auto_denoise.h"
#include "scanmesh/denoise.h"
#include "scanmesh/noise_analysis.h"
#include "stage.h"

namespace scanmesh::detail {
namespace {

// Loops that stopped moving at the noise's size (a relief's outline the curve fit would carry away).
std::string stopped_loops(const DenoiseReport& r) {
  if (r.boundary_loops_stopped == 0) return "";
  return "; " + std::to_string(r.boundary_loops_stopped) + " of " + std::to_string(r.boundary_loops) +
         " boundary loops stopped once they had moved as far as the noise";
}

// Pathological input (many faces on one spot or edge): say that neighbourhoods were cut to the nearest faces.
void warn_capped(const DenoiseReport& r, const Mesh& m, RunContext& ctx) {
  if (r.capped_neighbourhoods == 0) return;
  ctx.warnings.push_back("mesh.denoise: " + std::to_string(r.capped_neighbourhoods) + " of " + std::to_string(m.num_faces()) +
                         " faces had more neighbours within the radius than the limit; the nearest were used (many faces crowd "
                         "one spot or edge: a non-manifold fan, overlapping copies?)");
}

struct DenoiseStage : Stage {
  [[nodiscard]] bool reports_progress() const override { return true; }
  DenoiseOptions o;
  std::vector<std::string> given;  // explicit values win over `auto`
  void bind(Binder& b) override { bind_options(b, o, &given); }
  void run(Data& d, RunContext& ctx) override {
    Mesh& m = need_mesh(d, "mesh.denoise");
    if (!d.before && ctx.report_wanted) d.before = m;  // only a report shows the displacement
    const auto* progress = &ctx.options->progress;
    const ProgressCallback report_progress = [progress](int done, int total) {
      if (*progress) (*progress)("mesh.denoise", done, total);
    };
    char buf[640];
    if (!o.automatic) {
      if (o.scanned || o.vertices_are_points)
        ctx.warnings.emplace_back(std::string("mesh.denoise: ") + (o.scanned ? "scanned" : "vertices_are_points") +
                                  " only changes what auto chooses; without auto it has no effect");
      const DenoiseReport r = denoise(m, o, report_progress);
      if (r.exact_plane_fraction >= 0.1 && o.iterations > 0) {
        std::snprintf(buf, sizeof buf,
                      "mesh.denoise: %.0f%% of the vertices lay exactly in the plane of their faces: the mesh looked noise-free "
                      "(a CAD tessellation?); denoising may only have disturbed its triangles (auto: true leaves such meshes alone)",
                      100.0 * r.exact_plane_fraction);
        ctx.warnings.emplace_back(buf);
      }
      std::snprintf(buf, sizeof buf, "sigma_s %.3g, lambda %.3g, %d iteration%s, radius factor %.3g", o.sigma_s, o.lambda, r.iterations,
                    r.iterations == 1 ? "" : "s", o.radius_factor);
      details = buf + stopped_loops(r);
      warn_capped(r, m, ctx);
      return;
    }
    // A mesh this pipeline triangulated from a cloud is a scanned mesh unless the configuration says otherwise.
    DenoiseOptions run_options = o;
    if (d.scanned_mesh && std::find(given.begin(), given.end(), "scanned") == given.end()) run_options.scanned = true;
    // ...and its vertices are the points unless Poisson made it (or the configuration says it is no scan).
    if (run_options.scanned && d.scanned_mesh && d.mesh_keeps_points &&
        std::find(given.begin(), given.end(), "vertices_are_points") == given.end())
      run_options.vertices_are_points = true;
    const AutoReport a = denoise_auto(m, run_options, given, {}, report_progress);
    std::snprintf(buf, sizeof buf, "auto: noise %.3f x mean edge; %s: %s -> sigma_s %.3g, lambda %.3g, %d iteration%s (%s), radius factor %.3g; check %s",
                  a.noise_level, a.mode.c_str(), a.reason.c_str(), a.options.sigma_s, a.options.lambda, a.run.iterations,
                  a.run.iterations == 1 ? "" : "s", a.run.stop_reason.c_str(), a.options.radius_factor, a.check.c_str());
    details = buf + stopped_loops(a.run);
    if (a.unfold.folds > 0) {
      std::snprintf(buf, sizeof buf, "; folds unfolded %zu of %zu", a.unfold.folds - a.unfold.remaining, a.unfold.folds);
      details += buf;
    }
    decision_text = {{"mode", a.mode}, {"reason", a.reason}, {"stop_reason", a.run.stop_reason}, {"check", a.check},
                     {"scanned", run_options.scanned ? "true" : "false"},
                     {"vertices_are_points", run_options.vertices_are_points ? "true" : "false"}};
    decision_numbers = {{"noise_level", a.noise_level},
                        {"noise", a.noise},
                        {"exact_plane_fraction", a.exact_plane_fraction},
                        {"isolated_outlier_share", a.impulsive_share},
                        {"height_agreement", a.height_agreement}};
    // Shares the run did not measure (no probe ran, or its rule is off) are left out rather than shown as -1.
    for (const auto& [key, share] : {std::pair<const char*, double>{"soft_crease_share", a.crease_share},
                                     {"flat_edge_share", a.flat_share},
                                     {"flat_edge_share_half_probe", a.flat_share_half}})
      if (share >= 0.0) decision_numbers.emplace_back(key, share);
    decision_numbers.insert(decision_numbers.end(), {{"sigma_s", a.options.sigma_s},
                        {"lambda", a.options.lambda},
                        {"radius_factor", a.options.radius_factor},
                        {"iterations", static_cast<double>(a.run.iterations)},
                        {"probe_iterations", static_cast<double>(a.probe_iterations)},
                        {"levelled_at", static_cast<double>(a.levelled_at)},
                        {"ran_past_target", static_cast<double>(a.ran_past_target)},
                        {"flat_floor_from", static_cast<double>(a.flat_floor_from)},
                        {"flat_floor_to", static_cast<double>(a.flat_floor_to)},
                        {"displacement", a.run.displacement},
                        {"boundary_loops", static_cast<double>(a.run.boundary_loops)},
                        {"boundary_loops_stopped", static_cast<double>(a.run.boundary_loops_stopped)},
                        {"folds", static_cast<double>(a.unfold.folds)},
                        {"folds_left", static_cast<double>(a.unfold.remaining)},
                        {"mean_normal_move", a.mean_normal_move},
                        {"volume_change", a.volume_change}});
    warn_capped(a.run, m, ctx);
    if (a.shifted) {
      const double ratio = a.noise > 0.0 ? a.mean_normal_move / a.noise : 0.0;
      char volume[96] = "";
      if (a.volume_change != 0.0) std::snprintf(volume, sizeof volume, "; the enclosed volume changed by %+.2f%%", 100.0 * a.volume_change);
      std::snprintf(buf, sizeof buf,
                    "mesh.denoise: the surface moved %s by %.3g on average (%.2f x the noise estimate%s): it %s as a whole, where removing "
                    "noise moves vertices both ways alike. Usual cause: long edges beside short ones (the fidelity term pulls a "
                    "coarse curved patch towards its chords); with lambda 0 (no fidelity term) the volume holds",
                    ratio < 0.0 ? "against its normals" : "along its normals", std::abs(a.mean_normal_move), std::abs(ratio), volume,
                    a.volume_change < 0.0 ? "shrank" : a.volume_change > 0.0 ? "swelled" : "moved");
      ctx.warnings.emplace_back(buf);
    }
    if (a.check != "passed" && a.check != "not needed")
      ctx.warnings.push_back(a.run.iterations == 0
                                 ? "mesh.denoise: no iteration passed the result check (" + a.check +
                                       "): the mesh is left as it came, noise and all (a mesh whose faces overlap, such as a surface meshed twice, "
                                       "turns surface under any denoising)"
                                 : "mesh.denoise: the result check ended the run early (" + a.check + "); the last iteration that passed is kept");
  }
};

struct NoiseStage : Stage {
  NoiseOptions o;
  void bind(Binder& b) override { bind_options(b, o); }
  void run(Data& d, RunContext&) override {
    add_noise(need_mesh(d, "mesh.noise"), o);
    d.seed = o.seed;
    d.scanned_mesh = false;  // synthetic noise (impulsive, say) is not the scanner's
  }
};

}  // namespace

void register_denoise_stages(StageRegistry& r) {
  r.add("mesh.denoise", [] { return std::make_unique<DenoiseStage>(); });
  r.add("mesh.noise", [] { return std::make_unique<NoiseStage>(); });
}

}  // namespace scanmesh::detail
