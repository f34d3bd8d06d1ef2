// Records, for every pair of the tuning corpus (corpus.h), how the result's quality evolves with the
// iterations for a grid of fixed (sigma_s, lambda, radius factor) settings: MSAE, flipped faces and the
// displacement from the noisy input, at checkpoint iterations. One run to the last checkpoint gives every
// earlier one (the state after k iterations does not depend on the total), so the grid is cheap enough
// to fit --auto offline, with leave-one-model-out cross-validation (auto_cv).
// usage: scanmesh_auto_grid [DATA_DIR] [--only MODEL,...] [--skip MODEL,...] [--sigmas a,b,..] [--lambdas ..] [--radii ..]
//                           [--outliers a,b,..]   outlier_jump values (0: off; negative: that value with
//                                                 outlier_peaks; recorded as the curve's outlier key)
//                           [--sliver-guard G] > grid.csv   (G: the denoiser's sliver_guard, default its default)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "corpus.h"
#include "scanmesh/auto_denoise.h"
#include "scanmesh/denoise.h"
#include "scanmesh/noise_analysis.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/geometry.h"
#include "scanmesh/topology.h"
#include "guarded_main.h"

using namespace scanmesh;

namespace {

struct Quality {
  double msae = 0.0;
  std::size_t flips = 0;
};

Quality compare(const std::vector<Vec3>& positions, const std::vector<Face>& faces, const std::vector<Vec3>& clean_normals) {
  Quality q;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& t = faces[f];
    const Vec3 n = triangle_normal(positions[t[0]], positions[t[1]], positions[t[2]]);
    const double c = std::clamp(n.dot(clean_normals[f]), -1.0, 1.0);
    const double angle = std::acos(c) * 180.0 / 3.14159265358979323846;
    q.msae += angle;
    q.flips += c < 0.0 ? 1 : 0;
  }
  q.msae /= static_cast<double>(std::max<std::size_t>(1, faces.size()));
  return q;
}

}  // namespace

static int run(int argc, char** argv) {
  std::filesystem::path data = "../shared/data";
  std::string only, skip;
  std::vector<double> sigmas = {0.35, 0.5, 0.7, 1.0, 1.5}, lambdas = {0.05, 0.2, 0.5}, radii = {2.0};
  std::vector<double> outliers = {0.0};
  double sliver_guard = DenoiseOptions{}.sliver_guard;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
    else if (!std::strcmp(argv[i], "--skip") && i + 1 < argc) skip = argv[++i];
    else if (!std::strcmp(argv[i], "--sigmas") && i + 1 < argc) sigmas = bench::parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--lambdas") && i + 1 < argc) lambdas = bench::parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--radii") && i + 1 < argc) radii = bench::parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--outliers") && i + 1 < argc) outliers = bench::parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--sliver-guard") && i + 1 < argc) sliver_guard = std::atof(argv[++i]);
    else data = argv[i];
  }
  const auto models = bench::corpus_models(data);
  if (models.empty()) {
    std::printf("skipped: %s not found\n", data.c_str());
    return 0;
  }
  const std::vector<int> checkpoints = {1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 12,  14,  16,  18,  20,  23,  26,
                                        30, 35, 40, 45, 50, 60, 70, 80, 90, 100, 115, 130, 150, 175, 200};
  for (const auto& model : models) {
    if ((!only.empty() && !bench::listed(model, only)) || (!skip.empty() && bench::listed(model, skip))) continue;
    for (const auto& pair : bench::load_pairs(model)) {
      const auto t0 = std::chrono::steady_clock::now();
      FaceGeometry g;
      compute_face_geometry(pair.clean.positions, pair.clean.faces, g);
      const std::vector<Vec3> clean_normals = g.normals;
      const Quality input = compare(pair.noisy.positions, pair.noisy.faces, clean_normals);
      const Topology topo = build_topology(pair.noisy);
      const NoiseAnalysis na = analyse_noise(pair.noisy);
      const double share[4] = {0, 0, 0, 0};  // (columns kept for the analysis scripts)
      std::printf("P,%s,%s,%s,%zu,%.4f,%zu,%.5f,%.5f,%.5f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.4f,%.4f,%.4f,%.4f\n", pair.model.c_str(),
                  pair.variant.c_str(), pair.kind.c_str(), pair.noisy.num_faces(), input.msae, input.flips, na.level,
                  na.isolated_outlier_share, na.exact_plane_fraction, na.mean_edge, na.median_jump, 0.0, na.rms_jump,
                  na.trimmed_rms_jump, 0.0, share[0], share[1], share[2], share[3]);
      // Flip proxies: faces turned by more than 90 degrees from the input's normals, raw and smoothed (the
      // reference of --auto's result check, auto_denoise.cpp): what --auto can check without ground truth;
      // and the turned share by area, the check itself.
      const std::vector<Vec3> smooth_normals = prefiltered_normals(pair.noisy, 3.0, 2.0, 4);
      std::vector<Vec3> raw_normals;
      double input_turned_area = 0.0;
      {
        FaceGeometry pg;
        compute_face_geometry(pair.noisy.positions, pair.noisy.faces, pg);
        raw_normals = pg.normals;
        input_turned_area = turned_area_share(pg, smooth_normals);
      }
      std::size_t input_smooth_flips = 0;
      for (std::size_t f = 0; f < raw_normals.size(); ++f) input_smooth_flips += raw_normals[f].dot(smooth_normals[f]) < 0.0 ? 1 : 0;
      for (double r : radii)
        for (double s : sigmas)
          for (double l : lambdas)
            for (double ou : outliers) {
            Mesh m = pair.noisy;
            DenoiseOptions o;
            o.sigma_s = s;
            o.lambda = l;
            o.radius_factor = r;
            o.outlier_jump = std::abs(ou);
            o.outlier_peaks = ou < 0.0;
            o.sliver_guard = sliver_guard;
            o.iterations = checkpoints.back();
            std::size_t next = 0;
            FaceGeometry cg;
            denoise(m, o, {}, [&](int it, const std::vector<Vec3>& pos) {
              if (next >= checkpoints.size() || it != checkpoints[next]) return true;
              ++next;
              const Quality q = compare(pos, pair.noisy.faces, clean_normals);
              // Displacement from the noisy input, and its part along the current vertex normals.
              compute_face_geometry(pos, pair.noisy.faces, cg);
              const std::vector<Vec3> vn = vertex_normals(topo, cg);
              double d2 = 0.0, n2 = 0.0;
              std::size_t count = 0;
              for (std::size_t v = 0; v < pos.size(); ++v) {
                if (topo.vertex_faces.size(v) == 0) continue;
                const Vec3 d = pos[v] - pair.noisy.positions[v];
                d2 += d.squaredNorm();
                n2 += std::pow(d.dot(vn[v]), 2);
                ++count;
              }
              // Share of manifold edges whose dihedral angle exceeds 20 / 30 / 45 degrees in the current mesh.
              double sharp[3] = {0, 0, 0};
              std::size_t manifold = 0;
              for (std::size_t e = 0; e < topo.edges.size(); ++e) {
                if (topo.edge_faces.size(e) != 2) continue;
                ++manifold;
                const double c = cg.normals[topo.edge_faces.begin(e)[0]].dot(cg.normals[topo.edge_faces.begin(e)[1]]);
                sharp[0] += c < 0.9396926 ? 1 : 0;
                sharp[1] += c < 0.8660254 ? 1 : 0;
                sharp[2] += c < 0.7071068 ? 1 : 0;
              }
              for (double& x : sharp) x /= static_cast<double>(std::max<std::size_t>(1, manifold));
              std::size_t flips_raw = 0, flips_smooth = 0;
              for (std::size_t f = 0; f < cg.normals.size(); ++f) {
                flips_raw += cg.normals[f].dot(raw_normals[f]) < 0.0 ? 1 : 0;
                flips_smooth += cg.normals[f].dot(smooth_normals[f]) < 0.0 ? 1 : 0;
              }
              std::printf("C,%s,%s,%.2f,%.2f,%.1f,%.2f,%.2f,%d,%.4f,%zu,%.6g,%.6g,%.2f,%.5f,%.5f,%.5f,%zu,%zu,%zu,%.6g,%.6g,%.5f\n", pair.model.c_str(),
                          pair.variant.c_str(), s, l, r, 0.0, 0.0, it, q.msae, q.flips, std::sqrt(n2 / std::max<std::size_t>(1, count)),
                          std::sqrt(d2 / std::max<std::size_t>(1, count)), -ou, sharp[0], sharp[1], sharp[2], flips_raw, flips_smooth,
                          input_smooth_flips, turned_area_share(cg, smooth_normals), input_turned_area,
                          bend_share(cg, topo, -1.0, AutoRules{}.flat_max_deg));
              return true;
            });
          }
      std::fflush(stdout);
      std::fprintf(stderr, "%s %s: %zu faces, %.1f s\n", pair.model.c_str(), pair.variant.c_str(), pair.noisy.num_faces(),
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  }
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
