// Parameter sweep on the clean/noisy pairs: how the documented defaults and the --auto rules were chosen.
// usage: scanmesh_sweep PAIRS_DIR [model ...]   (prints one CSV row per model and parameter set)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "scanmesh/denoise.h"
#include "scanmesh/noise_analysis.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/geometry.h"
#include "scanmesh/mesh_io.h"
#include "guarded_main.h"

using namespace scanmesh;

static int run(int argc, char** argv) {
  namespace fs = std::filesystem;
  const fs::path dir = argc > 1 ? argv[1] : "../shared/data/pairs";
  if (!fs::is_directory(dir)) {
    std::printf("skipped: %s not found\n", dir.c_str());
    return 0;
  }
  std::vector<std::string> models(argv + std::min(argc, 2), argv + argc);
  if (models.empty())
    for (const auto& e : fs::directory_iterator(dir)) models.push_back(e.path().filename().string());
  const std::vector<double> sigmas = {0.25, 0.35, 0.45, 0.55, 0.7, 0.9, 1.2};
  const std::vector<double> lambdas = {0.05, 0.1, 0.2, 0.3};
  const std::vector<int> iterations = {5, 10, 20, 30, 45, 60, 80, 100, 150};
  std::printf("model,noise_est,sigma_s,lambda,iterations,msae,flips,q\n");
  for (const auto& name : models) {
    const Mesh clean = read_mesh((dir / name / "clean.obj").string());
    const Mesh noisy = read_mesh((dir / name / "noisy.obj").string());
    const double est = analyse_noise(noisy).level;
    for (double s : sigmas)
      for (double l : lambdas)
        for (int it : iterations) {
          Mesh m = noisy;
          DenoiseOptions o;
          o.sigma_s = s;
          o.lambda = l;
          o.iterations = it;
          o.feature_aware_fidelity = std::getenv("FEATURE_AWARE") != nullptr;
          if (std::getenv("DECAY")) o.decay = std::atof(std::getenv("DECAY"));
          denoise(m, o);
          const MeshMetrics mm = evaluate(m, nullptr);
          // MSAE and flips only (no distances): cheap enough for a sweep.
          double msae = 0.0;
          std::size_t flips = 0;
          for (std::size_t f = 0; f < m.num_faces(); ++f) {
            const auto& t = m.faces[f];
            const Vec3 n1 = triangle_normal(m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]);
            const Vec3 n2 = triangle_normal(clean.positions[t[0]], clean.positions[t[1]], clean.positions[t[2]]);
            const double ang = std::acos(std::clamp(n1.dot(n2), -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
            msae += ang;
            flips += ang > 90.0 ? 1 : 0;
          }
          msae /= static_cast<double>(m.num_faces());
          std::printf("%s,%.4f,%.2f,%.2f,%d,%.4f,%zu,%.4f\n", name.c_str(), est, s, l, it, msae, flips, mm.quality_mean);
          std::fflush(stdout);
        }
  }
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
