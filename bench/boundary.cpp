// How well an open mesh keeps its boundary: noise, denoise, then compare boundary and interior vertices.
// usage: scanmesh_boundary [MESH] [--free] [--level L]   (default ../shared/data/meshes/hemisphere-open.off)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "scanmesh/add_noise.h"
#include "scanmesh/auto_denoise.h"
#include "scanmesh/denoise.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/topology.h"
#include "guarded_main.h"

using namespace scanmesh;

namespace {

double loop_length(const Mesh& m, const std::vector<int>& loop) {
  double l = 0.0;
  for (std::size_t k = 0; k < loop.size(); ++k) l += (m.positions[loop[(k + 1) % loop.size()]] - m.positions[loop[k]]).norm();
  return l;
}

}  // namespace

static int run(int argc, char** argv) {
  std::string path = "../shared/data/meshes/hemisphere-open.off";
  DenoiseOptions o;
  NoiseOptions n;
  bool automatic = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--free")) o.keep_boundary = false;
    else if (!std::strcmp(argv[i], "--level") && i + 1 < argc) n.level = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--feature-aware")) o.feature_aware_fidelity = true;
    else if (!std::strcmp(argv[i], "--window") && i + 1 < argc) o.boundary_window = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--auto")) automatic = true;
    else path = argv[i];
  }
  if (!std::filesystem::exists(path)) {
    std::printf("skipped: %s not found\n", path.c_str());
    return 0;
  }
  const Mesh clean = read_mesh(path);
  Mesh noisy = clean;
  add_noise(noisy, n);
  Mesh out = noisy;
  if (automatic) {
    const AutoReport a = denoise_auto(out, o, {"keep_boundary", "boundary_window", "feature_aware_fidelity"});
    std::printf("auto: %s, %d iterations (%s)\n", a.mode.c_str(), a.run.iterations, a.run.stop_reason.c_str());
  } else {
    denoise(out, o);
  }
  const Topology t = build_topology(clean);
  for (const auto* m : {&noisy, &out}) {
    const MeshMetrics r = evaluate(*m, &clean);
    double eb = 0.0, ei = 0.0, db = 0.0, di = 0.0;
    std::size_t nb = 0, ni = 0;
    for (std::size_t v = 0; v < clean.num_vertices(); ++v) {
      const double moved = (m->positions[v] - clean.positions[v]).norm();
      if (t.boundary_vertex[v]) {
        eb += r.vertex_distance[v];
        db += moved;
        ++nb;
      } else {
        ei += r.vertex_distance[v];
        di += moved;
        ++ni;
      }
    }
    eb /= static_cast<double>(std::max<std::size_t>(nb, 1));
    ei /= static_cast<double>(std::max<std::size_t>(ni, 1));
    if (std::getenv("SPLIT")) {  // hemisphere only: radial and z error of boundary vertices
      double rad = 0.0, z = 0.0, sz = 0.0;
      for (std::size_t v = 0; v < clean.num_vertices(); ++v)
        if (t.boundary_vertex[v]) {
          rad += m->positions[v].norm() - 1.0;
          z += std::abs(m->positions[v].z() - clean.positions[v].z());
          sz += m->positions[v].z() - clean.positions[v].z();
        }
      double absr = 0.0, fb = 0.0, fi = 0.0;
      std::size_t cb = 0, ci = 0;
      for (std::size_t v = 0; v < clean.num_vertices(); ++v)
        if (t.boundary_vertex[v]) absr += std::abs(m->positions[v].norm() - 1.0);
      for (std::size_t f = 0; f < clean.num_faces(); ++f) {
        const Face& fc = clean.faces[f];
        if (t.boundary_vertex[fc[0]] || t.boundary_vertex[fc[1]] || t.boundary_vertex[fc[2]]) {
          fb += r.face_angle_error[f];
          ++cb;
        } else {
          fi += r.face_angle_error[f];
          ++ci;
        }
      }
      std::printf("  boundary mean(r-1) %.5f |r-1| %.5f |dz| %.5f dz %.5f; MSAE boundary faces %.3f interior %.3f\n", rad / nb,
                  absr / nb, z / nb, sz / nb, fb / cb, fi / ci);
    }
    double lc = 0.0, lm = 0.0;
    for (const auto& loop : t.boundary_loops) {
      lc += loop_length(clean, loop);
      lm += loop_length(*m, loop);
    }
    std::printf("%s: MSAE %.3f deg, mean distance to the clean surface: boundary %.5f interior %.5f (ratio %.2f); "
                "mean distance to the clean vertex: boundary %.5f interior %.5f (ratio %.2f); boundary length %+.2f%% vs clean\n",
                m == &noisy ? "noisy   " : "denoised", r.msae_deg, eb, ei, eb / ei, db / nb, di / ni, (db / nb) / (di / ni),
                100.0 * (lm - lc) / lc);
  }
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
