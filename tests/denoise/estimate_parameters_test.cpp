#include "scanmesh/estimate_parameters.h"

#include <gtest/gtest.h>

#include "helpers.h"
#include "scanmesh/add_noise.h"
#include "scanmesh/evaluate.h"

using namespace scanmesh;

TEST(EstimateParameters, NoiseLevelTracksTheTruth) {
  const Mesh clean = test::make_sphere(4);
  EXPECT_LT(estimate_noise_level(clean), 0.05);
  double previous = 0.0;
  for (double level : {0.1, 0.3, 0.6}) {
    Mesh m = clean;
    NoiseOptions o;
    o.level = level;
    add_noise(m, o);
    const double est = estimate_noise_level(m);
    // An indicator, not a measurement: it grows with the noise and stays within a factor of three of it.
    EXPECT_GT(est, level / 3.0) << "level " << level;
    EXPECT_LT(est, level * 1.5) << "level " << level;
    EXPECT_GT(est, previous * 1.2);
    previous = est;
  }
}

TEST(EstimateParameters, AutoDenoisesACube) {
  const Mesh clean = test::make_cube(10);
  Mesh m = clean;
  NoiseOptions n;
  n.level = 0.4;
  add_noise(m, n);
  const AutoParameters a = estimate_parameters(m);
  EXPECT_GT(a.feature_fraction, 0.0);
  denoise(m, a.options);
  const MeshMetrics r = evaluate(m, &clean);
  EXPECT_LT(r.msae_deg, 3.0);
  EXPECT_EQ(r.flipped_faces, 0u);
}

TEST(EstimateParameters, CleanMeshGetsLightTouch) {
  const Mesh clean = test::make_sphere(3);
  Mesh m = clean;
  const AutoParameters a = estimate_parameters(m);
  denoise(m, a.options);
  const MeshMetrics r = evaluate(m, &clean);
  EXPECT_LT(r.msae_deg, 1.0);
}

TEST(EstimateParameters, NoiseFreeTessellationIsLeftAlone) {
  // A clean CAD-like cube: most vertices lie exactly in the plane of their faces, which scanner noise
  // never produces; --auto must not shuffle such a mesh around.
  const Mesh cube = test::make_cube(6);
  EXPECT_GT(exact_plane_fraction(cube), 0.5);
  EXPECT_EQ(estimate_parameters(cube).options.iterations, 0);
  Mesh noisy = cube;
  NoiseOptions n;
  n.level = 0.1;
  add_noise(noisy, n);
  EXPECT_LT(exact_plane_fraction(noisy), 0.01);
  EXPECT_GT(estimate_parameters(noisy).options.iterations, 0);
}
