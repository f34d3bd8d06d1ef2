// Denoising pairs made the way scans are: a model ray-cast from several views twice with the same rays,
// once without depth noise and once with it; greedy projection of the noise-free points (cleaned up as the
// main job does) is the clean mesh, the same faces over the noisy points the noisy one. So the noise is a
// scanner's (along each ray, growing with depth, views overlapping with different directions) on a
// triangulation of scanned points, which the corpus (noise added to clean meshes' vertices) does not have.
// Prints, per model: MSAE against the clean mesh of the noisy input, the defaults, `--auto` (its mode and
// iterations), the bi-Laplacian peer, and the best iteration of the wide (2.0, 0.2) and the
// feature-keeping (0.7, 0.2) kernels (radius 3) on their curves, for comparison with `--auto`'s stop.
// usage: scanmesh_scan_pairs [DATA_DIR] [--views N] [--pixels WxH] [--scan-noise S] [--models a,b,...]
//                            [--write DIR]   (writes MODEL-clean.ply / MODEL-noisy.ply there)
//                            [--flips]       (the noisy mesh's edges flipped towards Delaunay, as the main job does)
// Skips cleanly if DATA_DIR is absent.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "guarded_main.h"
#include "peers.h"
#include "scan_pair.h"
#include "scan_options.h"
#include "scanmesh/auto_denoise.h"
#include "scanmesh/denoise.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/mesh_io.h"

using namespace scanmesh;
namespace fs = std::filesystem;

namespace {

// The lowest MSAE along a kernel's run and the iteration it came at.
std::pair<double, int> best_on_curve(const Mesh& noisy, const Mesh& clean, double sigma_s, int iterations) {
  DenoiseOptions o;
  o.sigma_s = sigma_s;
  o.lambda = 0.2;
  o.radius_factor = 3.0;
  o.iterations = iterations;
  Mesh m = noisy, at = noisy;
  std::pair<double, int> best{1e9, 0};
  denoise(m, o, {}, [&](int it, const std::vector<Vec3>& pos) {
    at.positions = pos;
    const double e = evaluate(at, &clean).msae_deg;
    if (e < best.first) best = {e, it};
    return true;
  });
  return best;
}

}  // namespace

static int run(int argc, char** argv) {
  fs::path data = "../shared/data";
  std::string model_list = "bunny,fandisk,spot,homer,rocker-arm,cow,cheburashka,teapot", write_dir;
  bool flips = false;
  VirtualScanOptions vo;
  vo.views = 6;
  vo.width = 160;
  vo.height = 120;
  vo.noise = 0.4;
  for (int i = 1; i < argc; ++i) {
    if (bench::read_scan_option(i, argc, argv, vo)) continue;
    if (!std::strcmp(argv[i], "--models") && i + 1 < argc) model_list = argv[++i];
    else if (!std::strcmp(argv[i], "--write") && i + 1 < argc) write_dir = argv[++i];
    else if (!std::strcmp(argv[i], "--flips")) flips = true;
    else data = argv[i];
  }
  if (!fs::is_directory(data / "train")) {
    std::printf("skipped: %s not found\n", (data / "train").c_str());
    return 0;
  }
  const std::unordered_map<std::string, fs::path> shared = {{"bunny", data / "pairs" / "bunny-0.2" / "clean.obj"},
                                                            {"fandisk", data / "pairs" / "fandisk-0.3" / "clean.obj"}};
  std::printf("## Scan pairs: %d views of %d x %d pixels, depth noise %g (MSAE in degrees against greedy projection of the noise-free scan%s)\n\n",
              vo.views, vo.width, vo.height, vo.noise, flips ? ", edges flipped towards Delaunay" : "");
  std::printf("| model | faces | noisy | defaults | --auto | mode, iterations | bi-Laplacian, 10 its | wide kernel at its best | feature-keeping at its best |\n"
              "|---|---|---|---|---|---|---|---|---|\n");
  std::stringstream names(model_list);
  for (std::string name; std::getline(names, name, ',');) {
    const auto s = shared.find(name);
    const fs::path file = s != shared.end() ? s->second : data / "train" / (name + ".obj");
    if (!fs::exists(file)) continue;
    Mesh clean, noisy;
    if (!bench::make_scan_pair(read_mesh(file.string()), vo, clean, noisy, flips)) {
      std::printf("| %s | the two scans do not line up | | | | | | | |\n", name.c_str());
      continue;
    }
    if (!write_dir.empty()) {
      write_mesh(clean, write_dir + "/" + name + "-clean.ply");
      write_mesh(noisy, write_dir + "/" + name + "-noisy.ply");
    }
    Mesh d = noisy;
    denoise(d, DenoiseOptions{});
    Mesh a = noisy;
    DenoiseOptions scanned;  // as the main job runs it on the meshes it makes
    scanned.scanned = true;
    scanned.vertices_are_points = true;  // greedy projection's mesh: its vertices are the points
    const AutoReport r = denoise_auto(a, scanned);
    Mesh b = noisy;
    bench::bilaplacian_smooth(b, bench::kBilaplacianIterations);
    const auto wide = best_on_curve(noisy, clean, 2.0, 40);
    const auto narrow = best_on_curve(noisy, clean, 0.7, 200);
    std::printf("| %s | %zu | %.2f | %.2f | %.2f | %s, %d | %.2f | %.2f at %d | %.2f at %d |\n", name.c_str(), clean.num_faces(),
                evaluate(noisy, &clean).msae_deg, evaluate(d, &clean).msae_deg, evaluate(a, &clean).msae_deg, r.mode.c_str(),
                r.run.iterations, evaluate(b, &clean).msae_deg, wide.first, wide.second, narrow.first, narrow.second);
    std::fflush(stdout);
  }
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
