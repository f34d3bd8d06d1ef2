#include "peers.h"

#include <vector>

#include "scanmesh/topology.h"

namespace scanmesh::bench {

void bilaplacian_smooth(Mesh& mesh, int iterations) {
  const Topology topo = build_topology(mesh);
  const std::size_t nv = mesh.num_vertices();
  std::vector<Vec3> u(nv, Vec3::Zero());
  std::vector<Vec3>& p = mesh.positions;
  for (int it = 0; it < iterations; ++it) {
    // u = L p: the umbrella vector (mean of the neighbours minus the vertex).
    for (std::size_t v = 0; v < nv; ++v) {
      const int n = topo.vertex_vertices.size(v);
      if (n == 0) {
        u[v].setZero();
        continue;
      }
      Vec3 mean = Vec3::Zero();
      for (const int* j = topo.vertex_vertices.begin(v); j != topo.vertex_vertices.end(v); ++j) mean += p[*j];
      u[v] = mean / n - p[v];
    }
    // L^2 p = (mean of the neighbours' u) - u; its diagonal 1 + sum_j 1 / (n_i n_j).
    std::vector<Vec3> next = p;
    for (std::size_t v = 0; v < nv; ++v) {
      const int n = topo.vertex_vertices.size(v);
      if (n == 0 || topo.boundary_vertex[v]) continue;
      Vec3 mean = Vec3::Zero();
      double diag = 1.0;
      for (const int* j = topo.vertex_vertices.begin(v); j != topo.vertex_vertices.end(v); ++j) {
        mean += u[*j];
        const int nj = topo.vertex_vertices.size(*j);
        if (nj > 0) diag += 1.0 / (static_cast<double>(n) * nj);
      }
      const Vec3 uu = mean / n - u[v];
      next[v] = p[v] - uu / diag;
    }
    p.swap(next);
  }
}

}  // namespace scanmesh::bench
