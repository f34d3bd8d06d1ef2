// --auto on meshes triangulated from scans (bench/scan_pair.h): a scanner's noise on greedy projection's
// triangles, which the tuning corpus (noise added to clean meshes' vertices) does not have.
#include <gtest/gtest.h>

#include "helpers.h"
#include "scan_pair.h"
#include "scanmesh/auto_denoise.h"
#include "scanmesh/evaluate.h"

using namespace scanmesh;

namespace {

// A smooth model with relief: the 5k-face unit sphere, bumps of 5% of its radius.
Mesh bumpy_sphere() { return test::make_bumpy_sphere(4); }

// A dense scan of it under strong depth noise: six views of 160 x 120.
void sphere_scan_pair(Mesh& clean, Mesh& noisy) {
  VirtualScanOptions vo;
  vo.views = 6;
  vo.width = 160;
  vo.height = 120;
  vo.noise = 0.4;
  ASSERT_TRUE(bench::make_scan_pair(bumpy_sphere(), vo, clean, noisy));
}

}  // namespace

// The pair is what the bench and this test rely on: the same faces, the noise-free mesh's vertices on the
// model's surface (the rays' hits), the noisy one's off it.
TEST(ScanPairs, TheCleanMeshLiesOnTheModelAndTheNoisyOneHasItsFaces) {
  const Mesh model = bumpy_sphere();
  Mesh clean, noisy;
  sphere_scan_pair(clean, noisy);
  ASSERT_EQ(clean.faces, noisy.faces);
  ASSERT_EQ(clean.num_vertices(), noisy.num_vertices());
  EXPECT_LT(evaluate(clean, &model).ev_relative, 1e-9);
  EXPECT_GT(evaluate(noisy, &model).ev_relative, 1e-4);
}

// On a scanned triangulation the wide kernel's displacement creeps past its target while the normals keep
// improving and the soft creases keep falling fast: the crease-fall continuation runs it further, and it
// ends closer to the clean mesh than the run stopped at its target.
TEST(ScanPairs, TheWideKernelGoesOnWhileTheCreasesOfAScannedTriangulationFall) {
  Mesh clean, noisy;
  sphere_scan_pair(clean, noisy);
  Mesh with = noisy, without = noisy;
  AutoRules off;
  off.smooth_crease_fall = 0.0;
  const AutoReport a = denoise_auto(with, {});
  const AutoReport b = denoise_auto(without, {}, {}, off);
  ASSERT_EQ(a.mode, "smooth") << a.reason;
  EXPECT_GT(a.ran_past_target, 0) << a.reason;
  EXPECT_GT(a.run.iterations, b.run.iterations) << a.reason;
  EXPECT_LT(evaluate(with, &clean).msae_deg, evaluate(without, &clean).msae_deg) << a.reason;
}
