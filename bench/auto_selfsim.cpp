// Self-simulation for the wide kernel's stop (an experiment docs/EXPERIMENTS.md reports; not what --auto does): for
// every corpus pair --auto (shipped rules) takes as smooth, its result is noised again along the normals
// at the level the input reads (scaled once so the re-noised mesh reads the same), the wide kernel runs on
// that copy, and the iteration where it comes closest to the result (ground truth by construction) is
// compared with --auto's stop and with the real pair's best iteration (MSAE against the clean mesh).
// usage: scanmesh_auto_selfsim [DATA_DIR] [--only MODEL]
#include <cmath>
#include <cstdio>
#include <string>

#include "corpus.h"
#include "scanmesh/add_noise.h"
#include "scanmesh/auto_denoise.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/noise_analysis.h"
#include "guarded_main.h"

using namespace scanmesh;

static int run(int argc, char** argv) {
  const auto models = bench::corpus_models_from_args(argc, argv);
  if (!models) return 0;
  for (const auto& model : *models) {
    if (model.name == "dragon-202k") continue;
    for (const auto& pair : bench::load_pairs(model)) {
      if (pair.variant.find("impulsive") != std::string::npos) continue;
      Mesh d = pair.noisy;
      const AutoReport r = denoise_auto(d, DenoiseOptions{});
      if (r.mode != "smooth") continue;
      // The real pair's curve: its best iteration.
      DenoiseOptions o = r.options;
      o.iterations = 30;
      o.target_displacement = 0.0;
      Mesh t = pair.noisy;
      int best_it = 0;
      double best = evaluate(pair.noisy, &pair.clean).msae_deg;
      Mesh x = pair.noisy;  // the iteration's positions on the pair's faces, for evaluate()
      denoise(t, o, {}, [&](int it, const std::vector<Vec3>& pos) {
        x.positions = pos;
        const double e = evaluate(x, &pair.clean).msae_deg;
        if (e < best) best = e, best_it = it;
        return true;
      });
      // Self-simulation: the result noised again along its normals so that it reads the input's noise level.
      const double target_level = r.noise_level;
      NoiseOptions no;
      no.direction = NoiseDirection::normal;
      no.seed = 11;
      no.level = target_level;
      Mesh s = d;
      add_noise(s, no);
      const double got = analyse_noise(s).level;
      no.level = target_level * target_level / std::max(1e-9, got);
      s = d;
      add_noise(s, no);
      int sim_it = 0;
      double sim_best = evaluate(s, &d).msae_deg;
      Mesh s2 = s;
      denoise(s2, o, {}, [&](int it, const std::vector<Vec3>& pos) {
        x.positions = pos;  // (same faces)
        const double e = evaluate(x, &d).msae_deg;
        if (e < sim_best) sim_best = e, sim_it = it;
        return it < sim_it + 4;  // four iterations past the best so far: the curve has turned
      });
      // The real pair denoised for the iterations the simulation chose.
      Mesh u = pair.noisy;
      DenoiseOptions ou = o;
      ou.iterations = std::max(1, sim_it);
      denoise(u, ou);
      std::printf("%-16s %-28s auto %2d its %.2f | best %2d its %.2f | selfsim best %2d its -> %.2f (level %.3f sim %.3f)\n", pair.model.c_str(),
                  pair.variant.c_str(), r.run.iterations, evaluate(d, &pair.clean).msae_deg, best_it, best, sim_it,
                  evaluate(u, &pair.clean).msae_deg, target_level, analyse_noise(s).level);
      std::fflush(stdout);
    }
  }
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
