#include "scanmesh/noise_analysis.h"

#include <algorithm>
#include <cmath>

namespace scanmesh {
namespace {

// Makes the median-jump estimate read the noise level of Gaussian noise in random directions: measured
// on the noisy meshes of the standard pairs (ratios 0.77 to 1.18 after calibration).
constexpr double kCalibration = 0.9;

// Each interior vertex's signed height over the mean of its one-ring (`excluded` vertices left out), along
// its normal; `valid` flags the vertices that have one.
void vertex_heights(const Mesh& mesh, const Topology& topo, const FaceGeometry& geometry, const std::vector<std::uint8_t>* excluded,
                    std::vector<double>& height, std::vector<std::uint8_t>& valid) {
  auto out = [&](int j) { return excluded && (*excluded)[static_cast<std::size_t>(j)]; };
  const std::vector<Vec3> normals = vertex_normals(topo, geometry);
  const auto nv = static_cast<long>(mesh.num_vertices());
  height.assign(mesh.num_vertices(), 0.0);
  valid.assign(mesh.num_vertices(), 0);
#pragma omp parallel for schedule(static)
  for (long i = 0; i < nv; ++i) {
    const int n = topo.vertex_vertices.size(i);
    if (topo.boundary_vertex[i] || n < 3 || normals[i].isZero()) continue;
    Vec3 mean = Vec3::Zero();
    int m = 0;
    for (const int* j = topo.vertex_vertices.begin(i); j != topo.vertex_vertices.end(i); ++j)
      if (!out(*j)) mean += mesh.positions[*j], ++m;
    if (m < 3) continue;
    mean /= m;
    height[i] = normals[i].dot(mesh.positions[i] - mean);
    valid[i] = 1;
  }
}

// The jumps (vertex_jumps) from the heights.
std::vector<double> jumps_from_heights(const Topology& topo, const std::vector<double>& height, const std::vector<std::uint8_t>& valid,
                                       const std::vector<std::uint8_t>* excluded) {
  auto out = [&](int j) { return excluded && (*excluded)[static_cast<std::size_t>(j)]; };
  const auto nv = static_cast<long>(height.size());
  std::vector<double> jump(height.size(), -1.0);
#pragma omp parallel for schedule(static)
  for (long i = 0; i < nv; ++i) {
    if (!valid[i]) continue;
    double sum = 0.0;
    int n = 0;
    for (const int* j = topo.vertex_vertices.begin(i); j != topo.vertex_vertices.end(i); ++j)
      if (valid[*j] && !out(*j)) {
        sum += height[*j];
        ++n;
      }
    if (n >= 3) jump[i] = std::abs(height[i] - sum / n);
  }
  return jump;
}

// height_agreement() from the heights.
double agreement_from_heights(const Topology& topo, const std::vector<double>& height, const std::vector<std::uint8_t>& valid) {
  double mean = 0.0;
  std::size_t n = 0;
  for (std::size_t v = 0; v < height.size(); ++v)
    if (valid[v]) mean += height[v], ++n;
  if (n == 0) return 0.0;
  mean /= static_cast<double>(n);
  // The regression of the neighbours' mean height on the vertex's own (both about the mean height),
  // summed in vertex order.
  double cross = 0.0, own = 0.0;
  for (std::size_t v = 0; v < height.size(); ++v) {
    if (!valid[v]) continue;
    double sum = 0.0;
    int k = 0;
    for (const int* w = topo.vertex_vertices.begin(v); w != topo.vertex_vertices.end(v); ++w)
      if (valid[*w]) sum += height[*w], ++k;
    if (k == 0) continue;
    cross += (height[v] - mean) * (sum / k - mean);
    own += (height[v] - mean) * (height[v] - mean);
  }
  return own > 0.0 ? cross / own : 0.0;
}

}  // namespace

std::vector<double> vertex_jumps(const Mesh& mesh, const Topology& topo, const FaceGeometry& geometry,
                                 const std::vector<std::uint8_t>* excluded) {
  std::vector<double> height;
  std::vector<std::uint8_t> valid;
  vertex_heights(mesh, topo, geometry, excluded, height, valid);
  return jumps_from_heights(topo, height, valid, excluded);
}

double height_agreement(const Mesh& mesh, const Topology& topo, const FaceGeometry& g) {
  std::vector<double> height;
  std::vector<std::uint8_t> valid;
  vertex_heights(mesh, topo, g, nullptr, height, valid);
  return agreement_from_heights(topo, height, valid);
}

std::vector<std::uint8_t> outlier_vertices(const Mesh& mesh, const Topology& topo, const FaceGeometry& geometry,
                                           const std::vector<double>& jump, double limit_factor, bool peaks) {
  std::vector<std::uint8_t> out(mesh.num_vertices(), 0);
  std::vector<double> valid;
  for (double j : jump)
    if (j >= 0.0) valid.push_back(j);
  if (valid.empty()) return out;
  std::nth_element(valid.begin(), valid.begin() + static_cast<long>(valid.size() / 2), valid.end());
  const double limit = limit_factor * valid[valid.size() / 2];
  const auto nv = static_cast<long>(mesh.num_vertices());
  if (!peaks) {
    for (long v = 0; v < nv; ++v) out[v] = jump[v] > limit ? 1 : 0;
    return out;
  }
  // Over the limit and the largest among the neighbours not yet taken (flags of an earlier round only).
  auto take_peaks = [&](const std::vector<double>& j, const std::vector<std::uint8_t>& taken, std::vector<std::uint8_t>& result) {
#pragma omp parallel for schedule(static)
    for (long v = 0; v < nv; ++v) {
      if (taken[v] || !(j[v] > limit)) continue;
      bool peak = true;
      for (const int* w = topo.vertex_vertices.begin(v); w != topo.vertex_vertices.end(v) && peak; ++w) peak = taken[*w] || !(j[*w] > j[v]);
      if (peak) result[v] = 1;
    }
  };
  const std::vector<std::uint8_t> none(mesh.num_vertices(), 0);
  take_peaks(jump, none, out);
  const std::vector<std::uint8_t> first = out;
  take_peaks(vertex_jumps(mesh, topo, geometry, &first), first, out);
  return out;
}

double exact_plane_fraction(const Mesh& mesh, const Topology& topo, const FaceGeometry& g) {
  // Exactly planar vertices (a CAD tessellation, an already denoised mesh).
  std::size_t flat = 0, counted = 0;
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    if (topo.vertex_faces.size(i) == 0) continue;
    ++counted;
    const Vec3& n0 = g.normals[*topo.vertex_faces.begin(i)];
    bool same = n0.squaredNorm() > 0.0;
    for (const int* f = topo.vertex_faces.begin(i); same && f != topo.vertex_faces.end(i); ++f) same = (g.normals[*f] - n0).norm() < 1e-4;
    flat += same ? 1 : 0;
  }
  return counted > 0 ? static_cast<double>(flat) / static_cast<double>(counted) : 0.0;
}

NoiseAnalysis analyse_noise(const Mesh& mesh, const Topology& topo, const FaceGeometry& g) {
  NoiseAnalysis a;
  a.mean_edge = mean_edge_length(mesh, topo);
  a.exact_plane_fraction = exact_plane_fraction(mesh, topo, g);

  // (the heights once, for the jumps and the agreement)
  std::vector<double> height;
  std::vector<std::uint8_t> valid;
  vertex_heights(mesh, topo, g, nullptr, height, valid);
  const std::vector<double> jump = jumps_from_heights(topo, height, valid, nullptr);
  std::vector<double> sorted;
  for (double x : jump)
    if (x >= 0.0) sorted.push_back(x);
  if (sorted.empty() || !(a.mean_edge > 0.0)) return a;
  a.height_agreement = agreement_from_heights(topo, height, valid);
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();
  a.median_jump = sorted[n / 2];
  double sum2 = 0.0, trimmed2 = 0.0;
  const std::size_t keep = std::max<std::size_t>(1, n * 98 / 100);
  for (std::size_t k = 0; k < n; ++k) {
    sum2 += sorted[k] * sorted[k];
    if (k < keep) trimmed2 += sorted[k] * sorted[k];
  }
  a.rms_jump = std::sqrt(sum2 / static_cast<double>(n));
  a.trimmed_rms_jump = std::sqrt(trimmed2 / static_cast<double>(keep));
  // The median of |x| is 0.6745 sigma for Gaussian x.
  a.level = kCalibration * a.median_jump / 0.6745 / a.mean_edge;
  const double limit = 6.0 * a.median_jump;
  std::size_t isolated = 0;
  for (std::size_t v = 0; v < jump.size(); ++v) {
    if (!(jump[v] > limit)) continue;
    bool alone = true;
    for (const int* w = topo.vertex_vertices.begin(v); w != topo.vertex_vertices.end(v) && alone; ++w) alone = !(jump[*w] > limit);
    isolated += alone ? 1 : 0;
  }
  a.isolated_outlier_share = static_cast<double>(isolated) / static_cast<double>(n);
  return a;
}

NoiseAnalysis analyse_noise(const Mesh& mesh) {
  const Topology t = build_topology(mesh);
  FaceGeometry g;
  compute_face_geometry(mesh.positions, mesh.faces, g);
  return analyse_noise(mesh, t, g);
}

}  // namespace scanmesh
