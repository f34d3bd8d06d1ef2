// Measures candidate features for --auto's decisions on every pair of the tuning corpus, from the noisy
// mesh alone (what --auto can see): dihedral-angle statistics after a feature-keeping and after an
// isotropic pre-smoothing, and how coherent the sharp edges are (long feature lines or scattered noise).
// One line per pair: F,model,variant,feature=value,...  Joined with auto_grid's curves for fitting.
// usage: scanmesh_auto_features [DATA_DIR] [--skip MODEL]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>

#include "corpus.h"
#include "scanmesh/denoise.h"
#include "scanmesh/geometry.h"
#include "scanmesh/normal_filtering.h"
#include "scanmesh/topology.h"
#include "guarded_main.h"

using namespace scanmesh;

namespace {

struct EdgeStats {
  double above[4] = {0, 0, 0, 0};  // share of manifold edges with dihedral > 20, 30, 45, 60 degrees
  double lines = 0.0;              // share of sharp (> 40 deg) edges continued straight (< 30 deg) at both ends
  double line_faces = 0.0;         // share of faces next to such line edges
  double long_chains = 0.0;        // share of sharp (> 35 deg) edges in connected sharp-edge sets of >= 10 edges
  double mean_chain = 0.0;         // mean size of those sets
};

EdgeStats edge_stats(const Mesh& m, const std::vector<Vec3>* normals = nullptr) {
  const Topology t = build_topology(m);
  FaceGeometry g;
  compute_face_geometry(m.positions, m.faces, g);
  if (normals != nullptr) g.normals = *normals;
  EdgeStats s;
  std::vector<int> sharp_edges;
  std::size_t manifold = 0;
  const double limits[4] = {20, 30, 45, 60};
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    if (t.edge_faces.size(e) != 2) continue;
    ++manifold;
    const int a = t.edge_faces.begin(e)[0], b = t.edge_faces.begin(e)[1];
    const double angle = std::acos(std::clamp(g.normals[a].dot(g.normals[b]), -1.0, 1.0)) * 180.0 / M_PI;
    for (int k = 0; k < 4; ++k) s.above[k] += angle > limits[k] ? 1.0 : 0.0;
    if (angle > 35.0) sharp_edges.push_back(static_cast<int>(e));
  }
  for (double& x : s.above) x /= static_cast<double>(std::max<std::size_t>(1, manifold));
  // Union-find over sharp edges sharing a vertex.
  std::vector<int> parent(sharp_edges.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<int> first_at(m.num_vertices(), -1);
  for (std::size_t k = 0; k < sharp_edges.size(); ++k)
    for (int v : t.edges[sharp_edges[k]]) {
      if (first_at[v] < 0) first_at[v] = static_cast<int>(k);
      else parent[find(static_cast<int>(k))] = find(first_at[v]);
    }
  std::vector<int> size(sharp_edges.size(), 0);
  for (std::size_t k = 0; k < sharp_edges.size(); ++k) ++size[find(static_cast<int>(k))];
  double in_long = 0.0, sets = 0.0, total = 0.0;
  for (std::size_t k = 0; k < sharp_edges.size(); ++k) {
    if (size[k] == 0) continue;
    sets += 1.0;
    total += size[k];
    if (size[k] >= 10) in_long += size[k];
  }
  s.long_chains = sharp_edges.empty() ? 0.0 : in_long / static_cast<double>(sharp_edges.size());
  s.mean_chain = sets > 0 ? total / sets : 0.0;
  // Feature lines: a sharp edge whose ends each continue into exactly one other sharp edge, turning by
  // less than 30 degrees. Real creases are such lines; noise kept as false creases zigzags and branches.
  std::vector<std::vector<int>> at(m.num_vertices());
  std::vector<std::uint8_t> is40(t.edges.size(), 0);
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    if (t.edge_faces.size(e) != 2) continue;
    const int a = t.edge_faces.begin(e)[0], b = t.edge_faces.begin(e)[1];
    if (g.normals[a].dot(g.normals[b]) < std::cos(40.0 * M_PI / 180.0)) {
      is40[e] = 1;
      at[t.edges[e][0]].push_back(static_cast<int>(e));
      at[t.edges[e][1]].push_back(static_cast<int>(e));
    }
  }
  std::size_t n40 = 0, straight = 0;
  std::vector<std::uint8_t> face_on_line(m.num_faces(), 0);
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    if (!is40[e]) continue;
    ++n40;
    bool ok = true;
    for (int end = 0; end < 2 && ok; ++end) {
      const int v = t.edges[e][end], u = t.edges[e][1 - end];
      if (at[v].size() != 2) {
        ok = false;
        break;
      }
      const int f = at[v][0] == static_cast<int>(e) ? at[v][1] : at[v][0];
      const int w = t.edges[f][0] == v ? t.edges[f][1] : t.edges[f][0];
      const Vec3 d1 = (m.positions[v] - m.positions[u]).normalized(), d2 = (m.positions[w] - m.positions[v]).normalized();
      ok = d1.dot(d2) > std::cos(30.0 * M_PI / 180.0);
    }
    if (ok) {
      ++straight;
      for (const int* f = t.edge_faces.begin(e); f != t.edge_faces.end(e); ++f) face_on_line[*f] = 1;
    }
  }
  s.lines = n40 > 0 ? static_cast<double>(straight) / static_cast<double>(n40) : 0.0;
  std::size_t lf = 0;
  for (auto x : face_on_line) lf += x;
  s.line_faces = static_cast<double>(lf) / static_cast<double>(std::max<std::size_t>(1, m.num_faces()));
  return s;
}

}  // namespace

static int run(int argc, char** argv) {
  std::filesystem::path data = "../shared/data";
  std::string skip;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--skip") && i + 1 < argc) skip = argv[++i];
    else data = argv[i];
  }
  const auto models = bench::corpus_models(data);
  if (models.empty()) {
    std::printf("skipped: %s not found\n", data.c_str());
    return 0;
  }
  for (const auto& model : models) {
    if (model.name == skip) continue;
    for (const auto& pair : bench::load_pairs(model)) {
      const EdgeStats raw = edge_stats(pair.noisy);
      Mesh cad = pair.noisy, org = pair.noisy;
      DenoiseOptions oc;
      oc.sigma_s = 0.55;
      oc.lambda = 0.3;
      oc.iterations = 20;
      oc.radius_factor = 3.0;
      denoise(cad, oc);
      DenoiseOptions oo;
      oo.sigma_s = 2.0;
      oo.lambda = 0.2;
      oo.iterations = 6;
      oo.radius_factor = 3.0;
      denoise(org, oo);
      const EdgeStats c = edge_stats(cad), o = edge_stats(org);
      // The same on the noisy mesh's normals after six passes of the feature-keeping normal filter alone.
      FaceGeometry ng;
      const Topology nt = build_topology(pair.noisy);
      compute_face_geometry(pair.noisy.positions, pair.noisy.faces, ng);
      const double c_a = mean_centroid_distance(pair.noisy, nt, ng);
      const Adjacency nbh = face_neighbourhoods(nt, ng, 3.0 * c_a, NeighbourhoodKind::ball, max_neighbourhood_size(3.0));
      std::vector<Vec3> fn;
      FaceGeometry pg = ng;
      for (int pass = 0; pass < 6; ++pass) {
        filter_face_normals(pg, nbh, c_a, 0.55, RobustEstimator::tukey, fn);
        pg.normals = fn;
      }
      const EdgeStats nf = edge_stats(pair.noisy, &pg.normals);
      std::printf("F,%s,%s", pair.model.c_str(), pair.variant.c_str());
      const char* th[4] = {"20", "30", "45", "60"};
      for (int k = 0; k < 4; ++k) std::printf(",raw%s=%.5f", th[k], raw.above[k]);
      for (int k = 0; k < 4; ++k) std::printf(",cad%s=%.5f", th[k], c.above[k]);
      for (int k = 0; k < 4; ++k) std::printf(",org%s=%.5f", th[k], o.above[k]);
      std::printf(",cadlong=%.4f,cadchain=%.2f,orglong=%.4f,orgchain=%.2f,rawlong=%.4f", c.long_chains, c.mean_chain, o.long_chains,
                  o.mean_chain, raw.long_chains);
      std::printf(",cadlines=%.4f,cadlinefaces=%.4f,nflines=%.4f,nflinefaces=%.4f,nf30=%.5f,nf45=%.5f\n", c.lines, c.line_faces, nf.lines,
                  nf.line_faces, nf.above[1], nf.above[2]);
      std::fflush(stdout);
    }
  }
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
