#include "scanmesh/auto_denoise.h"

#include <gtest/gtest.h>

#include <cstring>

#include "helpers.h"
#include "scanmesh/add_noise.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/noise_analysis.h"
#include "scanmesh/parallel.h"

using namespace scanmesh;

namespace {

Mesh noisy(const Mesh& clean, double level, NoiseKind kind = NoiseKind::gaussian, std::uint64_t seed = 1) {
  Mesh m = clean;
  NoiseOptions n;
  n.level = level;
  n.kind = kind;
  n.seed = seed;
  add_noise(m, n);
  return m;
}

}  // namespace

TEST(NoiseAnalysis, LevelTracksTheTruth) {
  const Mesh clean = test::make_sphere(4);
  EXPECT_LT(analyse_noise(clean).level, 0.05);
  double previous = 0.0;
  for (double level : {0.1, 0.3, 0.6}) {
    const double est = analyse_noise(noisy(clean, level)).level;
    // An indicator, not a measurement: it grows with the noise and stays within a factor of three of it.
    EXPECT_GT(est, level / 3.0) << "level " << level;
    EXPECT_LT(est, level * 1.5) << "level " << level;
    EXPECT_GT(est, previous * 1.2);
    previous = est;
  }
}

TEST(NoiseAnalysis, ImpulsiveNoiseShowsIsolatedOutliers) {
  const Mesh clean = test::make_sphere(4);
  EXPECT_LT(analyse_noise(noisy(clean, 0.3)).isolated_outlier_share, 0.005);
  EXPECT_GT(analyse_noise(noisy(clean, 0.5, NoiseKind::impulsive)).isolated_outlier_share, 0.011);
}

TEST(AutoDenoise, KeepsTheEdgesOfANoisyCube) {
  const Mesh clean = test::make_cube(10);
  Mesh m = noisy(clean, 0.4);
  const AutoReport a = denoise_auto(m, {});
  EXPECT_EQ(a.mode, "sharp") << a.reason;
  const MeshMetrics r = evaluate(m, &clean);
  EXPECT_LT(r.msae_deg, 3.0);
  EXPECT_EQ(r.flipped_faces, 0u);
}

// A noisy cube has almost no soft creases once the probe has run: it is clearly machined, so the displacement stop is
// lifted and its flat faces keep improving; with the rule off the same run stops at the target.
TEST(AutoDenoise, AClearlyMachinedPartRunsPastTheDisplacementTarget) {
  const Mesh clean = test::make_cube(24);
  Mesh input = clean;
  NoiseOptions n;
  n.level = 0.4;
  n.direction = NoiseDirection::normal;
  n.seed = 1;
  add_noise(input, n);
  Mesh with = input, without = input;
  AutoRules off;
  off.clear_sharp_share = 0.0;
  const AutoReport a = denoise_auto(with, {}, {}, AutoRules{});
  const AutoReport b = denoise_auto(without, {}, {}, off);
  ASSERT_EQ(a.mode, "sharp") << a.reason;
  ASSERT_EQ(b.mode, "sharp") << b.reason;
  EXPECT_EQ(b.run.stop_reason, "target displacement");
  EXPECT_NE(a.run.stop_reason, "target displacement");
  EXPECT_GT(a.run.iterations, b.run.iterations);
  EXPECT_LE(evaluate(with, &clean).msae_deg, evaluate(without, &clean).msae_deg);
}

TEST(AutoDenoise, DenoisesASphereWithoutShrinkingIt) {
  const Mesh clean = test::make_sphere(4);
  Mesh m = noisy(clean, 0.3);
  const double before = evaluate(m, &clean).msae_deg;
  denoise_auto(m, {});
  const MeshMetrics r = evaluate(m, &clean);
  EXPECT_LT(r.msae_deg, 0.3 * before);
  EXPECT_LT(std::abs(*r.volume_change), 0.02);
}

TEST(AutoDenoise, ImpulsiveNoiseMovesOnlyTheOutliers) {
  const Mesh clean = test::make_sphere(4);
  Mesh m = noisy(clean, 0.5, NoiseKind::impulsive);
  const Mesh input = m;
  const double before = evaluate(m, &clean).msae_deg;
  const AutoReport a = denoise_auto(m, {});
  EXPECT_EQ(a.mode, "impulsive") << a.reason;
  std::size_t moved = 0;
  for (std::size_t v = 0; v < m.num_vertices(); ++v) moved += m.positions[v] != input.positions[v] ? 1 : 0;
  EXPECT_LT(moved, m.num_vertices() / 4);  // about a tenth are hit
  EXPECT_LT(evaluate(m, &clean).msae_deg, 0.5 * before);
}

TEST(AutoDenoise, LeavesNoiseFreeTessellationsAlone) {
  // A clean CAD-like cube: most vertices lie exactly in the plane of their faces, which scanner noise
  // never produces; --auto must not shuffle such a mesh around.
  const Mesh cube = test::make_cube(6);
  Mesh m = cube;
  const AutoReport a = denoise_auto(m, {});
  EXPECT_EQ(a.mode, "untouched");
  EXPECT_EQ(m.positions, cube.positions);
}

TEST(AutoDenoise, BarelyTouchesACleanSmoothMesh) {
  const Mesh clean = test::make_sphere(3);
  Mesh m = clean;
  denoise_auto(m, {});
  EXPECT_LT(evaluate(m, &clean).msae_deg, 1.0);
}

TEST(AutoDenoise, ExplicitValuesWin) {
  const Mesh clean = test::make_sphere(3);
  Mesh m = noisy(clean, 0.3);
  DenoiseOptions given;
  given.sigma_s = 0.45;
  given.iterations = 7;
  const AutoReport a = denoise_auto(m, given, {"sigma_s", "iterations"});
  EXPECT_EQ(a.options.sigma_s, 0.45);
  EXPECT_EQ(a.run.iterations, 7);
}

TEST(AutoDenoise, IsIndependentOfTheThreadCount) {
  const Mesh clean = test::make_cube(8);
  for (NoiseKind kind : {NoiseKind::gaussian, NoiseKind::impulsive}) {
    const Mesh input = noisy(clean, 0.4, kind, 3);
    Mesh a = input, b = input;
    set_thread_count(1);
    denoise_auto(a, {});
    set_thread_count(2);
    denoise_auto(b, {});
    set_thread_count(0);
    EXPECT_EQ(std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(Vec3)), 0);
  }
}
