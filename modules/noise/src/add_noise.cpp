#include "scanmesh/add_noise.h"

#include <cmath>
#include <random>

#include "scanmesh/errors.h"
#include "scanmesh/geometry.h"
#include "scanmesh/topology.h"

namespace scanmesh {
namespace {

// std::normal_distribution differs between standard libraries; these helpers make the noise a pure
// function of the seed (mt19937_64 itself is specified exactly by the standard).
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }  // [0, 1)
  double normal() {
    // Box-Muller; 1 - u keeps the logarithm finite.
    const double u = 1.0 - uniform(), v = uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * 3.14159265358979323846 * v);
  }
  Vec3 direction() {
    const double z = 2.0 * uniform() - 1.0;
    const double phi = 2.0 * 3.14159265358979323846 * uniform();
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace

NoiseKind parse_noise_kind(const std::string& name) {
  if (name == "gaussian") return NoiseKind::gaussian;
  if (name == "uniform") return NoiseKind::uniform;
  if (name == "impulsive") return NoiseKind::impulsive;
  throw UsageError("unknown noise kind '" + name + "'; choose gaussian, uniform or impulsive");
}

NoiseDirection parse_noise_direction(const std::string& name) {
  if (name == "random") return NoiseDirection::random;
  if (name == "normal") return NoiseDirection::normal;
  throw UsageError("unknown noise direction '" + name + "'; choose random or normal");
}

double add_noise(Mesh& mesh, const NoiseOptions& o) {
  if (!std::isfinite(o.level) || o.level < 0.0) throw UsageError("noise level must be >= 0; got " + std::to_string(o.level));
  if (!(o.impulsive_fraction > 0.0 && o.impulsive_fraction <= 1.0))
    throw UsageError("impulsive fraction must be in (0, 1]; got " + std::to_string(o.impulsive_fraction));
  // Only the edges and the vertex -> face lists are read: no face -> face table.
  const Topology topology = build_topology(mesh, false);
  const double sigma = o.level * mean_edge_length(mesh, topology);
  std::vector<Vec3> normals;
  if (o.direction == NoiseDirection::normal) {
    FaceGeometry g;
    compute_face_geometry(mesh.positions, mesh.faces, g);
    normals = vertex_normals(topology, g);
  }
  Random rng(o.seed);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    // Draw the same number of values for every vertex so a vertex's noise does not depend on the others.
    const Vec3 random_dir = rng.direction();
    const double gauss = rng.normal();
    const double unif = rng.uniform();
    const double hit = rng.uniform();
    double amount = 0.0;
    switch (o.kind) {
      case NoiseKind::gaussian: amount = sigma * gauss; break;
      case NoiseKind::uniform: amount = sigma * std::sqrt(3.0) * (2.0 * unif - 1.0); break;
      case NoiseKind::impulsive: amount = hit < o.impulsive_fraction ? sigma * gauss : 0.0; break;
    }
    const Vec3 dir = o.direction == NoiseDirection::normal ? normals[v] : random_dir;
    mesh.positions[v] += amount * dir;
  }
  return sigma;
}

}  // namespace scanmesh
