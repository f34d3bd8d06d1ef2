#include "scanmesh/estimate_parameters.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "scanmesh/geometry.h"
#include "scanmesh/topology.h"

namespace scanmesh {

double estimate_noise_level(const Mesh& mesh) {
  const Topology topo = build_topology(mesh);
  const double edge = mean_edge_length(mesh, topo);
  if (!(edge > 0.0)) return 0.0;
  const auto nv = static_cast<long>(mesh.num_vertices());
  std::vector<double> d(mesh.num_vertices(), -1.0);
#pragma omp parallel for schedule(static)
  for (long i = 0; i < nv; ++i) {
    const int n = topo.vertex_vertices.size(i);
    if (topo.boundary_vertex[i] || n < 4) continue;
    Vec3 mean = Vec3::Zero();
    for (const int* j = topo.vertex_vertices.begin(i); j != topo.vertex_vertices.end(i); ++j) mean += mesh.positions[*j];
    mean /= n;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const int* j = topo.vertex_vertices.begin(i); j != topo.vertex_vertices.end(i); ++j) {
      const Vec3 q = mesh.positions[*j] - mean;
      cov += q * q.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const Vec3 normal = es.eigenvectors().col(0);
    d[i] = std::abs(normal.dot(mesh.positions[i] - mean));
  }
  std::vector<double> valid;
  for (double x : d)
    if (x >= 0.0) valid.push_back(x);
  if (valid.empty()) return 0.0;
  std::nth_element(valid.begin(), valid.begin() + valid.size() / 2, valid.end());
  // For Gaussian noise the median of |x| is 0.6745 sigma.
  return valid[valid.size() / 2] / 0.6745 / edge;
}

AutoParameters estimate_parameters(const Mesh& mesh, const DenoiseOptions& base) {
  AutoParameters a;
  a.options = base;
  a.noise_level = estimate_noise_level(mesh);
  return a;
}

}  // namespace scanmesh
