#include "scanmesh/add_noise.h"

#include <gtest/gtest.h>

#include <cmath>

#include "helpers.h"
#include "scanmesh/errors.h"
#include "scanmesh/geometry.h"

using namespace scanmesh;

TEST(Noise, SeededAndReproducible) {
  const Mesh clean = test::make_sphere(3);
  Mesh a = clean, b = clean, c = clean;
  NoiseOptions o;
  add_noise(a, o);
  add_noise(b, o);
  o.seed = 2;
  add_noise(c, o);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_NE(a.positions, c.positions);
  EXPECT_EQ(a.faces, clean.faces);
}

TEST(Noise, GaussianStandardDeviationIsLevelTimesMeanEdge) {
  const Mesh clean = test::make_sphere(4);
  const double edge = mean_edge_length(clean, build_topology(clean));
  for (auto kind : {NoiseKind::gaussian, NoiseKind::uniform}) {
    Mesh m = clean;
    NoiseOptions o;
    o.level = 0.3;
    o.kind = kind;
    const double sigma = add_noise(m, o);
    EXPECT_NEAR(sigma, 0.3 * edge, 1e-15);
    double sum2 = 0.0;
    for (std::size_t v = 0; v < m.num_vertices(); ++v) sum2 += (m.positions[v] - clean.positions[v]).squaredNorm();
    const double rms = std::sqrt(sum2 / static_cast<double>(m.num_vertices()));
    EXPECT_NEAR(rms / sigma, 1.0, 0.05);
  }
}

TEST(Noise, NormalDirectionAndImpulsiveFraction) {
  const Mesh clean = test::make_sphere(4);
  Mesh m = clean;
  NoiseOptions o;
  o.direction = NoiseDirection::normal;
  add_noise(m, o);
  for (std::size_t v = 0; v < m.num_vertices(); ++v) {
    const Vec3 d = m.positions[v] - clean.positions[v];
    // Area-weighted vertex normals of an icosphere are within a degree of radial.
    EXPECT_LT(d.cross(clean.positions[v]).norm(), 0.02 * d.norm() + 1e-15);
  }
  m = clean;
  o = NoiseOptions{};
  o.kind = NoiseKind::impulsive;
  o.impulsive_fraction = 0.2;
  add_noise(m, o);
  std::size_t moved = 0;
  for (std::size_t v = 0; v < m.num_vertices(); ++v) moved += m.positions[v] != clean.positions[v] ? 1 : 0;
  EXPECT_NEAR(static_cast<double>(moved) / static_cast<double>(m.num_vertices()), 0.2, 0.03);
}

TEST(Noise, RejectsBadOptions) {
  Mesh m = test::make_grid(2);
  NoiseOptions o;
  o.level = -1;
  EXPECT_THROW(add_noise(m, o), UsageError);
  EXPECT_THROW(parse_noise_kind("pink"), UsageError);
  EXPECT_THROW(parse_noise_direction("up"), UsageError);
}
