// Records, for every pair of the tuning corpus (corpus.h), how the result's quality evolves with the
// iterations for a grid of fixed (sigma_s, lambda, radius factor) settings: MSAE, flipped faces and the
// displacement from the noisy input, at checkpoint iterations. One run to the last checkpoint gives every
// earlier one (the state after k iterations does not depend on the total), so the grid is cheap enough
// to fit --auto offline, with leave-one-model-out cross-validation (auto_cv).
// usage: scanmesh_auto_grid [DATA_DIR] [--only MODEL] [--sigmas a,b,..] [--lambdas ..] [--radii ..] > grid.csv
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "corpus.h"
#include "scanmesh/denoise.h"
#include "scanmesh/estimate_parameters.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/geometry.h"
#include "scanmesh/normal_filtering.h"
#include "scanmesh/topology.h"

using namespace scanmesh;

namespace {

std::vector<double> parse_list(const char* s) {
  std::vector<double> v;
  std::stringstream in(s);
  std::string tok;
  while (std::getline(in, tok, ',')) v.push_back(std::atof(tok.c_str()));
  return v;
}

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

int main(int argc, char** argv) {
  std::filesystem::path data = "../shared/data";
  std::string only, skip;
  std::vector<double> sigmas = {0.35, 0.5, 0.7, 1.0, 1.5}, lambdas = {0.05, 0.2, 0.5}, radii = {2.0};
  std::vector<double> smooth = {0.0}, thresholds = {0.5}, caps = {0.0}, outliers = {0.0};
  double mask_fraction = 0.0;  // > 0: self-supervised probe runs on a masked copy (M lines)
  double prefilter_sigma = 2.0;
  int prefilter_passes = 2;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
    else if (!std::strcmp(argv[i], "--skip") && i + 1 < argc) skip = argv[++i];
    else if (!std::strcmp(argv[i], "--sigmas") && i + 1 < argc) sigmas = parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--lambdas") && i + 1 < argc) lambdas = parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--radii") && i + 1 < argc) radii = parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--smooth") && i + 1 < argc) smooth = parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--thresholds") && i + 1 < argc) thresholds = parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--caps") && i + 1 < argc) caps = parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--outliers") && i + 1 < argc) outliers = parse_list(argv[++i]);
    else if (!std::strcmp(argv[i], "--mask") && i + 1 < argc) mask_fraction = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--prefilter") && i + 2 < argc) {
      prefilter_sigma = std::atof(argv[++i]);
      prefilter_passes = std::atoi(argv[++i]);
    }
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
    if ((!only.empty() && model.name != only) || model.name == skip) continue;
    for (const auto& pair : bench::load_pairs(model)) {
      const auto t0 = std::chrono::steady_clock::now();
      FaceGeometry g;
      compute_face_geometry(pair.clean.positions, pair.clean.faces, g);
      const std::vector<Vec3> clean_normals = g.normals;
      const Quality input = compare(pair.noisy.positions, pair.noisy.faces, clean_normals);
      const AutoParameters a = estimate_parameters(pair.noisy);
      const Topology topo = build_topology(pair.noisy);
      // Noise statistics (mesh units) and the share of faces whose pre-filtered neighbourhood bends by more
      // than 0.3 / 0.5 / 0.7 / 1.0, for fitting rules offline.
      std::vector<double> jumps = noise_jumps(pair.noisy);
      std::sort(jumps.begin(), jumps.end());
      auto quantile = [&](double q) { return jumps.empty() ? 0.0 : jumps[std::min(jumps.size() - 1, static_cast<std::size_t>(q * jumps.size()))]; };
      double sum = 0.0, sum2 = 0.0, trimmed2 = 0.0;
      for (std::size_t k = 0; k < jumps.size(); ++k) {
        sum += jumps[k];
        sum2 += jumps[k] * jumps[k];
        if (k < jumps.size() * 98 / 100) trimmed2 += jumps[k] * jumps[k];
      }
      const double nj = static_cast<double>(std::max<std::size_t>(1, jumps.size()));
      double share[4] = {0, 0, 0, 0};
      {
        FaceGeometry ng;
        compute_face_geometry(pair.noisy.positions, pair.noisy.faces, ng);
        const double c_a = mean_centroid_distance(pair.noisy, topo, ng);
        const Adjacency nbh = face_neighbourhoods(topo, ng, 3.0 * c_a, NeighbourhoodKind::ball, max_neighbourhood_size(3.0));
        const std::vector<double> phi = feature_strength(ng, nbh, c_a, 2, 2.0);
        const double t[4] = {0.3, 0.5, 0.7, 1.0};
        for (double x : phi)
          for (int k = 0; k < 4; ++k) share[k] += x > t[k] ? 1.0 / static_cast<double>(phi.size()) : 0.0;
      }
      std::printf("P,%s,%s,%s,%zu,%.4f,%zu,%.5f,%.5f,%.5f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.4f,%.4f,%.4f,%.4f\n", pair.model.c_str(),
                  pair.variant.c_str(), pair.kind.c_str(), pair.noisy.num_faces(), input.msae, input.flips, a.noise_level,
                  a.feature_fraction, a.exact_plane_fraction, mean_edge_length(pair.noisy, topo), quantile(0.5), sum / nj,
                  std::sqrt(sum2 / nj), std::sqrt(trimmed2 / nj), quantile(0.9), share[0], share[1], share[2], share[3]);
      for (double r : radii)
        for (double s : sigmas)
          for (double l : lambdas)
            for (double sm : smooth)
              for (double th : (sm > 0.0 ? thresholds : std::vector<double>{0.0}))
                for (double cp0 : caps)
                  for (double ou : outliers) {
            const double cp = ou > 0.0 ? -ou : cp0;  // the csv's last column: cap, or -threshold for outlier runs
            if (sm > 0.0 && sm <= s) continue;
            Mesh m = pair.noisy;
            // Masked probe: a sparse set of interior vertices (no two adjacent) is moved to the mean of its
            // one-ring, so the denoiser never sees their noisy positions; how far the result lands from those
            // positions (along the normal) estimates the error plus the noise, without ground truth.
            std::vector<int> masked;
            if (mask_fraction > 0.0) {
              std::vector<std::uint8_t> blocked(m.num_vertices(), 0);
              std::uint64_t h = 88172645463325252ull;
              std::vector<int> order(m.num_vertices());
              for (std::size_t v = 0; v < order.size(); ++v) order[v] = static_cast<int>(v);
              for (std::size_t v = order.size(); v > 1; --v) {
                h ^= h << 13, h ^= h >> 7, h ^= h << 17;
                std::swap(order[v - 1], order[h % v]);
              }
              const std::size_t want = static_cast<std::size_t>(mask_fraction * m.num_vertices());
              for (int v : order) {
                if (masked.size() >= want) break;
                if (blocked[v] || topo.boundary_vertex[v] || topo.vertex_vertices.size(v) < 3) continue;
                masked.push_back(v);
                blocked[v] = 1;
                for (const int* w = topo.vertex_vertices.begin(v); w != topo.vertex_vertices.end(v); ++w) blocked[*w] = 1;
              }
              for (int v : masked) {
                Vec3 c = Vec3::Zero();
                for (const int* w = topo.vertex_vertices.begin(v); w != topo.vertex_vertices.end(v); ++w) c += pair.noisy.positions[*w];
                m.positions[v] = c / topo.vertex_vertices.size(v);
              }
            }
            DenoiseOptions o;
            o.sigma_s = s;
            o.lambda = l;
            o.radius_factor = r;
            o.smooth_sigma_s = sm;
            o.feature_threshold = th;
            o.feature_prefilter_sigma = prefilter_sigma;
            o.feature_prefilter_passes = prefilter_passes;
            o.displacement_cap = cp0;
            o.outlier_jump = ou;
            o.iterations = checkpoints.back();
            std::size_t next = 0;
            FaceGeometry cg;
            denoise(m, o, {}, [&](int it, const std::vector<Vec3>& pos) {
              if (next >= checkpoints.size() || it != checkpoints[next]) return;
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
              if (!masked.empty()) {
                double loss = 0.0;
                for (int v : masked) loss += std::pow((pos[v] - pair.noisy.positions[v]).dot(vn[v]), 2);
                std::printf("M,%s,%s,%.2f,%.2f,%.1f,%.2f,%.2f,%d,%.4f,%.8g,%.2f\n", pair.model.c_str(), pair.variant.c_str(), s, l, r, sm, th, it,
                            q.msae, loss / static_cast<double>(masked.size()), cp);
                return;
              }
              std::printf("C,%s,%s,%.2f,%.2f,%.1f,%.2f,%.2f,%d,%.4f,%zu,%.6g,%.6g,%.2f\n", pair.model.c_str(), pair.variant.c_str(), s, l, r,
                          sm, th, it, q.msae, q.flips, std::sqrt(n2 / std::max<std::size_t>(1, count)), std::sqrt(d2 / std::max<std::size_t>(1, count)), cp);
            });
          }
      std::fflush(stdout);
      std::fprintf(stderr, "%s %s: %zu faces, %.1f s\n", pair.model.c_str(), pair.variant.c_str(), pair.noisy.num_faces(),
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  }
  return 0;
}
