// Flatness of the pre-filtered normal field, per corpus pair: the share of faces whose smoothed normal
// (four passes of the wide robust filter, what --auto's result check compares with) lies within a few
// degrees of the mean smoothed normal of its surroundings (radius R c_a). Machined parts are mostly flat
// faces; organic shapes bend everywhere. A candidate feature for --auto's sharp/smooth decision.
// usage: scanmesh_auto_flatness [DATA_DIR] [MESH ...]   (CSV on stdout; extra meshes are scored too)
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "corpus.h"
#include "scanmesh/geometry.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/noise_analysis.h"
#include "scanmesh/normal_filtering.h"
#include "scanmesh/topology.h"
#include "guarded_main.h"

using namespace scanmesh;

namespace {

void score(const std::string& model, const std::string& variant, const Mesh& mesh) {
  const Topology topo = build_topology(mesh);
  FaceGeometry g;
  compute_face_geometry(mesh.positions, mesh.faces, g);
  const double c_a = mean_centroid_distance(mesh, topo, g);
  const Adjacency nbh = face_neighbourhoods(topo, g, 3.0 * c_a, NeighbourhoodKind::ball, max_neighbourhood_size(3.0));
  std::vector<Vec3> filtered;
  FaceGeometry s = g;
  for (int pass = 0; pass < 4; ++pass) {
    filter_face_normals(s, nbh, c_a, 2.0, RobustEstimator::tukey, filtered);
    s.normals = filtered;
  }
  std::printf("%s,%s,%.5f", model.c_str(), variant.c_str(), analyse_noise(mesh).level);
  for (double radius : {3.0, 5.0}) {
    const Adjacency wide = face_neighbourhoods(topo, s, radius * c_a, NeighbourhoodKind::ball, max_neighbourhood_size(radius));
    for (double deg : {2.0, 4.0, 8.0}) {
      const double c = std::cos(deg * 3.14159265358979323846 / 180.0);
      double flat = 0.0, total = 0.0;
      for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
        Vec3 mean = Vec3::Zero();
        for (const int* j = wide.begin(f); j != wide.end(f); ++j) mean += s.areas[*j] * s.normals[*j];
        if (!(mean.norm() > 0.0)) continue;
        flat += g.areas[f] * (s.normals[f].dot(mean.normalized()) >= c ? 1.0 : 0.0);
        total += g.areas[f];
      }
      std::printf(",%.4f", total > 0 ? flat / total : 0.0);
    }
  }
  std::printf("\n");
  std::fflush(stdout);
}

}  // namespace

static int run(int argc, char** argv) {
  std::string data = "../shared/data";
  std::vector<std::string> extra;
  for (int i = 1; i < argc; ++i) (i == 1 ? data : extra.emplace_back()) = argv[i];
  const auto models = bench::corpus_models(data);
  if (models.empty() && extra.empty()) {  // (the other corpus benches skip the same way)
    std::printf("skipped: %s not found\n", data.c_str());
    return 0;
  }
  std::printf("model,variant,level,r3_2,r3_4,r3_8,r5_2,r5_4,r5_8\n");
  for (const auto& model : models)
    for (const auto& pair : bench::load_pairs(model)) score(pair.model, pair.variant, pair.noisy);
  for (const auto& f : extra) score(f, "extra", read_mesh(f));
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
