// --auto with its shipped rules on every pair of the tuning corpus, next to the noisy input and the plain
// defaults and a peer, bi-Laplacian smoothing with 10 iterations (peers.h) (MSAE in degrees against the
// clean mesh / flipped faces). A quick check of a change to --auto;
// the held-back (leave-one-model-out) figures come from scanmesh_auto_cv table.
// usage: scanmesh_auto_corpus [DATA_DIR] [--only MODEL] [--mesh CLEAN_FILE ...] [--write-pairs DIR]
//        --write-pairs DIR also writes each pair's meshes (MODEL-clean.ply, MODEL-VARIANT.ply) to DIR, to
//        rerun one with the command line
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "corpus.h"
#include "peers.h"
#include "scanmesh/auto_denoise.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/mesh_io.h"
#include "guarded_main.h"

using namespace scanmesh;

static int run(int argc, char** argv) {
  std::string write_dir;
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--write-pairs") && i + 1 < argc) write_dir = argv[++i];
    else args.push_back(argv[i]);
  }
  const auto models = bench::corpus_models_from_args(static_cast<int>(args.size()), args.data());
  if (!models) return 0;
  if (!write_dir.empty()) std::filesystem::create_directories(write_dir);
  std::printf("model,variant,noisy_msae,noisy_flips,default_msae,default_flips,auto_msae,auto_flips,mode,iterations,"
              "noisy_slivers,default_slivers,auto_slivers,bilaplacian_msae,bilaplacian_flips\n");
  // Slivers: faces whose circumradius exceeds 3x their shortest edge (equilateral: 0.577).
  auto slivers = [](const MeshMetrics& m) { return std::count_if(m.face_quality.begin(), m.face_quality.end(), [](double q) { return q > 3.0; }); };
  int wins = 0, total = 0, worse = 0;
  for (const auto& model : *models) {
    for (const auto& pair : bench::load_pairs(model)) {
      const MeshMetrics noisy = evaluate(pair.noisy, &pair.clean);
      if (!write_dir.empty()) {
        // Named by the model (a dense version shares its coarse original's group, not its files).
        write_mesh(pair.clean, write_dir + "/" + model.name + "-clean.ply");
        write_mesh(pair.noisy, write_dir + "/" + model.name + "-" + pair.variant + ".ply");
      }
      Mesh d = pair.noisy;
      denoise(d, DenoiseOptions{});
      const MeshMetrics dm = evaluate(d, &pair.clean);
      Mesh a = pair.noisy;
      const AutoReport r = denoise_auto(a, DenoiseOptions{});
      const MeshMetrics am = evaluate(a, &pair.clean);
      Mesh b = pair.noisy;
      bench::bilaplacian_smooth(b, bench::kBilaplacianIterations);
      const MeshMetrics bm = evaluate(b, &pair.clean);
      std::printf("%s,%s,%.3f,%zu,%.3f,%zu,%.3f,%zu,%s,%d,%ld,%ld,%ld,%.3f,%zu\n", pair.model.c_str(), pair.variant.c_str(), noisy.msae_deg,
                  noisy.flipped_faces, dm.msae_deg, dm.flipped_faces, am.msae_deg, am.flipped_faces, r.mode.c_str(), r.run.iterations,
                  static_cast<long>(slivers(noisy)), static_cast<long>(slivers(dm)), static_cast<long>(slivers(am)), bm.msae_deg,
                  bm.flipped_faces);
      std::fflush(stdout);
      ++total;
      wins += am.msae_deg < dm.msae_deg ? 1 : 0;
      worse += am.msae_deg > noisy.msae_deg || am.flipped_faces > noisy.flipped_faces ? 1 : 0;
    }
  }
  std::printf("# --auto better than the defaults on %d of %d pairs; worse than the noisy input (MSAE or flips) on %d\n", wins, total, worse);
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
