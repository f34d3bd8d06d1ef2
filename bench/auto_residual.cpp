// Residual features of candidate runs on the tuning corpus: for each pair, each candidate kernel and each
// checkpoint, the quality against the clean mesh (what --auto cannot see) next to what it can see: how far
// the vertices moved along the normals (against the noise estimate) and how the removed part, the residual
// r = n . (noisy - result), is structured: its correlation between neighbouring vertices and with the
// result's mean curvature. Noise is white and blind to the shape; what over-smoothing removes is neither.
// usage: scanmesh_auto_residual [DATA_DIR] [--only MODEL]   (CSV on stdout)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "corpus.h"
#include "scanmesh/denoise.h"
#include "scanmesh/geometry.h"
#include "scanmesh/noise_analysis.h"
#include "scanmesh/topology.h"
#include "guarded_main.h"

using namespace scanmesh;

namespace {

struct Features {
  double msae = 0.0;
  long flips = 0;
  double ndisp = 0.0;      // RMS residual (normal component), mesh units
  double neighbour = 0.0;  // correlation of the residual between edge-adjacent vertices
  double curvature = 0.0;  // correlation of the residual with the result's mean-curvature normal component
};

Features measure(const Mesh& noisy, const std::vector<Vec3>& pos, const Topology& topo, const std::vector<Vec3>& clean_normals) {
  Features f;
  FaceGeometry g;
  compute_face_geometry(pos, noisy.faces, g);
  for (std::size_t k = 0; k < g.normals.size(); ++k) {
    const double c = std::clamp(g.normals[k].dot(clean_normals[k]), -1.0, 1.0);
    const double a = std::acos(c) * 180.0 / 3.14159265358979323846;
    f.msae += a;
    f.flips += a > 90.0 ? 1 : 0;
  }
  f.msae /= static_cast<double>(std::max<std::size_t>(1, g.normals.size()));
  const std::vector<Vec3> vn = vertex_normals(topo, g);
  const std::size_t nv = pos.size();
  std::vector<double> r(nv, 0.0), h(nv, 0.0);
  std::vector<char> used(nv, 0);
  for (std::size_t v = 0; v < nv; ++v) {
    if (topo.vertex_faces.size(v) == 0 || topo.boundary_vertex[v]) continue;
    used[v] = 1;
    r[v] = (noisy.positions[v] - pos[v]).dot(vn[v]);
    Vec3 lap = Vec3::Zero();
    const int n = topo.vertex_vertices.size(v);
    for (const int* w = topo.vertex_vertices.begin(v); w != topo.vertex_vertices.end(v); ++w) lap += pos[*w];
    h[v] = (lap / n - pos[v]).dot(vn[v]);  // > 0 where the surface bends away from the normal (concave side)
  }
  double rr = 0.0, hh = 0.0, rh = 0.0, rn = 0.0, cnt = 0.0;
  for (std::size_t v = 0; v < nv; ++v)
    if (used[v]) rr += r[v] * r[v], hh += h[v] * h[v], rh += r[v] * h[v], cnt += 1.0;
  double pair_sum = 0.0, pair_norm = 0.0;
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    const auto [a, b] = topo.edges[e];
    if (!used[a] || !used[b]) continue;
    pair_sum += r[a] * r[b];
    pair_norm += 0.5 * (r[a] * r[a] + r[b] * r[b]);
  }
  (void)rn;
  f.ndisp = cnt > 0 ? std::sqrt(rr / cnt) : 0.0;
  f.neighbour = pair_norm > 0 ? pair_sum / pair_norm : 0.0;
  f.curvature = rr > 0 && hh > 0 ? rh / std::sqrt(rr * hh) : 0.0;
  return f;
}

}  // namespace

static int run(int argc, char** argv) {
  const auto models = bench::corpus_models_from_args(argc, argv);
  if (!models) return 0;
  const std::vector<int> checkpoints = {1, 2, 3, 4, 5, 6, 8, 10, 12, 14, 17, 20, 25, 30, 40, 50, 60, 80, 100, 130, 160, 200};
  struct Candidate {
    double sigma, lambda, radius;
    int max_it;
  };
  const std::vector<Candidate> candidates = {{0.7, 0.2, 3.0, 200}, {0.7, 0.2, 2.0, 200}, {1.0, 0.3, 3.0, 60}, {1.5, 0.3, 3.0, 40},
                                             {2.0, 0.2, 3.0, 40}};
  std::printf("model,variant,kind,faces,noisy_msae,level,noise,sigma,lambda,radius,it,msae,flips,ndisp,neighbour,curvature\n");
  for (const auto& model : *models) {
    for (const auto& pair : bench::load_pairs(model)) {
      const auto t0 = std::chrono::steady_clock::now();
      FaceGeometry cg;
      compute_face_geometry(pair.clean.positions, pair.clean.faces, cg);
      const Topology topo = build_topology(pair.noisy);
      const NoiseAnalysis na = analyse_noise(pair.noisy);
      const Features input = measure(pair.noisy, pair.noisy.positions, topo, cg.normals);
      for (const auto& c : candidates) {
        Mesh m = pair.noisy;
        DenoiseOptions o;
        o.sigma_s = c.sigma;
        o.lambda = c.lambda;
        o.radius_factor = c.radius;
        o.iterations = c.max_it;
        std::size_t next = 0;
        denoise(m, o, {}, [&](int it, const std::vector<Vec3>& pos) {
          if (next >= checkpoints.size() || it != checkpoints[next]) return true;
          ++next;
          const Features f = measure(pair.noisy, pos, topo, cg.normals);
          std::printf("%s,%s,%s,%zu,%.4f,%.5f,%.6g,%.2f,%.2f,%.1f,%d,%.4f,%ld,%.6g,%.4f,%.4f\n", pair.model.c_str(), pair.variant.c_str(),
                      pair.kind.c_str(), pair.noisy.num_faces(), input.msae, na.level, na.trimmed_rms_jump, c.sigma, c.lambda, c.radius, it,
                      f.msae, f.flips, f.ndisp, f.neighbour, f.curvature);
          return true;
        });
      }
      std::fflush(stdout);
      std::fprintf(stderr, "%s %s: %.1f s\n", pair.model.c_str(), pair.variant.c_str(),
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  }
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
