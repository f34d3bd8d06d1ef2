// --auto on meshes triangulated from scans (bench/scan_pair.h): a scanner's noise on greedy projection's
// triangles, which the tuning corpus (noise added to clean meshes' vertices) does not have.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "helpers.h"
#include "scan_pair.h"
#include "scanmesh/auto_denoise.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/clean_mesh.h"
#include "scanmesh/mesh_cloud.h"
#include "scanmesh/neighbourhoods.h"
#include "scanmesh/point_cloud.h"
#include "scanmesh/virtual_scan.h"

using namespace scanmesh;

namespace {

// `views` views of `width` x `height` pixels, depth noise `noise` (x the model's mean edge).
VirtualScanOptions scan_options(int views, int width, int height, double noise) {
  VirtualScanOptions vo;
  vo.views = views;
  vo.width = width;
  vo.height = height;
  vo.noise = noise;
  return vo;
}

// A smooth model with relief: the 5k-face unit sphere, bumps of 5% of its radius.
Mesh bumpy_sphere() { return test::make_bumpy_sphere(4); }

// A dense scan of it under strong depth noise: six views of 160 x 120.
void sphere_scan_pair(Mesh& clean, Mesh& noisy) {
  const VirtualScanOptions vo = scan_options(6, 160, 120, 0.4);
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

// The continuation's floor (soft creases above the probe's limit) keeps a smooth mesh given noise, whose
// last creases fall however long it is smoothed, from running away; on a triangulation of scanned points
// the wide kernel's best iterations lie well past it, and the run with the scans' lower floor ends closer
// to the clean mesh.
TEST(ScanPairs, AScannedTriangulationRunsOnPastTheCreaseFloor) {
  Mesh clean, noisy;
  sphere_scan_pair(clean, noisy);
  DenoiseOptions points;
  points.scanned = points.vertices_are_points = true;
  AutoRules floor;
  floor.points_crease_floor = -1.0;  // the probe's limit, as on meshes given noise
  Mesh without = noisy, with = noisy;
  const AutoReport a = denoise_auto(without, points);
  const AutoReport b = denoise_auto(with, points, {}, floor);
  ASSERT_EQ(a.mode, "smooth") << a.reason;
  EXPECT_GT(a.run.iterations, b.run.iterations) << a.reason << "\n" << b.reason;
  EXPECT_LT(evaluate(without, &clean).msae_deg, evaluate(with, &clean).msae_deg) << a.reason;
}

// A sparse scan under weak noise (eight views of 64 x 48, the bench's sparsest setting): greedy
// projection's irregular triangles over the points. Evening them out at the fidelity weight fitted on the
// corpus moves the vertices off the surface by more than the noise had; with the weight lowered under weak
// noise on meshes whose vertices are the points, the result ends closer to the clean mesh. The weight of
// the feature-keeping run, on which the sharp/smooth decision was fitted, is not touched.
TEST(ScanPairs, ASparseScanUnderWeakNoiseIsNotEvenedOutOffItsSurface) {
  const VirtualScanOptions vo = scan_options(8, 64, 48, 0.1);
  Mesh clean, noisy;
  ASSERT_TRUE(bench::make_scan_pair(bumpy_sphere(), vo, clean, noisy));
  DenoiseOptions points;
  points.scanned = points.vertices_are_points = true;
  AutoRules off;
  off.scanned_lambda_level = 0.0;
  Mesh lowered = noisy, fitted = noisy;
  const AutoReport a = denoise_auto(lowered, points);
  const AutoReport b = denoise_auto(fitted, points, {}, off);
  ASSERT_EQ(a.mode, "smooth") << a.reason;
  EXPECT_LT(a.options.lambda, 0.5 * AutoRules{}.smooth_lambda) << a.reason;
  EXPECT_EQ(b.options.lambda, AutoRules{}.smooth_lambda);
  EXPECT_LT(evaluate(lowered, &clean).msae_deg, evaluate(fitted, &clean).msae_deg) << a.reason;
}

namespace {

// A ball of radius 0.8 resting on a 4 x 4 ground plane, the scene tilted by 70 degrees about x so that the
// first view of the virtual scanner sees it obliquely: the ball hides part of the plane behind it.
Mesh ball_on_a_plane() {
  Mesh m = test::make_grid(40, 0.1);
  for (auto& p : m.positions) p -= Vec3(2, 2, 0);
  const Mesh ball = test::make_sphere(4);
  const int first = static_cast<int>(m.positions.size());
  for (const Vec3& p : ball.positions) m.positions.push_back(0.8 * p + Vec3(0, 0, 0.8));
  for (const Face& f : ball.faces) m.faces.push_back({f[0] + first, f[1] + first, f[2] + first});
  const double a = 70.0 * M_PI / 180.0;
  for (auto& p : m.positions) p = Vec3(p.x(), std::cos(a) * p.y() - std::sin(a) * p.z(), std::sin(a) * p.y() + std::cos(a) * p.z());
  return m;
}

// mesh.auto on a scan of it from `views` views, normals as the main job estimates them.
MeshingDecision mesh_scan_of_ball_on_a_plane(int views) {
  PointCloud c = merge_views(virtual_scan(ball_on_a_plane(), scan_options(views, 160, 120, 0.2)));
  estimate_normals(c, NormalOptions{});
  MeshingDecision d;
  mesh_cloud(c, MeshMethodOptions{}, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, measure_scale(c), &d);
  return d;
}

double decision_number(const MeshingDecision& d, const std::string& key) {
  for (const auto& [k, v] : d.numbers)
    if (k == key) return v;
  return -1.0;
}

}  // namespace

// Seen from one side, the plane behind the ball is a region the scanner did not see: greedy projection
// leaves a gap there that no patch within the trim distance of the points can close. That gap must not
// send a single view to Poisson, whose open surface lies farther from the truth.
TEST(MeshCloud, ASingleViewKeepsGreedyProjectionWithTheGapItDidNotSee) {
  const MeshingDecision one = mesh_scan_of_ball_on_a_plane(1);
  EXPECT_GE(decision_number(one, "one_sided_normals"), 0.9);
  EXPECT_EQ(one.method, MeshMethod::gp3) << one.reason;
  EXPECT_NE(one.reason.find("one-sided, as a single view: the gaps left open are regions no view saw"), std::string::npos) << one.reason;
  // Four views of the same scene see it from several sides.
  EXPECT_LT(decision_number(mesh_scan_of_ball_on_a_plane(4), "one_sided_normals"), 0.9);
}

// A bowl (an open hemisphere) scanned from views all round sees both of its sides, each view's normals
// facing its own sensor. Greedy projection meshes the two sides' points in overlapping pieces that cover
// every point and leave no hole (its pieces lie over one another); mesh.auto must see that and give one
// layer: the largest, the pieces over it removed (or Poisson, if that fits the points better).
TEST(MeshCloud, GreedyProjectionThatMeshesABowlTwiceIsNotKept) {
  const VirtualScanOptions vo = scan_options(10, 96, 72, 0.2);
  PointCloud c = merge_views(virtual_scan(test::make_cap(24, 96, 0.5 * M_PI), vo));
  estimate_normals(c, NormalOptions{});  // as the main job: surface normals, each facing the sensor that saw the point
  const CloudScale s = measure_scale(c);
  Mesh gp3 = triangulate_gp3(c, Gp3Options{}, s);
  clean_mesh(gp3, CleanupOptions{});
  const ScanFit twice = measure_scan_fit(gp3, c.points, s.spacing);
  const ScanFitLimits limits;
  ASSERT_GT(twice.layered_share, limits.max_layered_share);  // the failure this test is about
  EXPECT_GE(twice.coverage, limits.min_coverage);
  bool layer_problem = false;
  for (const auto& p : scan_fit_problems(twice)) layer_problem = layer_problem || p.find("meshed twice") != std::string::npos;
  EXPECT_TRUE(layer_problem);

  MeshingDecision d;
  const Mesh m = mesh_cloud(c, MeshMethodOptions{}, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, s, &d);
  ASSERT_FALSE(m.faces.empty()) << d.reason;
  EXPECT_LE(d.fit.layered_share, limits.max_layered_share) << d.reason;
  EXPECT_GE(d.fit.coverage, limits.min_coverage) << d.reason;
  EXPECT_NE(d.reason.find("lying over others"), std::string::npos) << d.reason;
  // One layer: greedy projection's pieces together have about 1.6 times its area (each of the noisy
  // layers has more area than the bowl's 2 pi: the noise's roughness).
  FaceGeometry g;
  compute_face_geometry(m.positions, m.faces, g);
  double area = 0.0, twice_area = 0.0;
  for (double a : g.areas) area += a;
  compute_face_geometry(gp3.positions, gp3.faces, g);
  for (double a : g.areas) twice_area += a;
  EXPECT_LT(area, 0.75 * twice_area) << d.reason;
}

// Where no feature-keeping iteration passes the result check before the probe, --auto returns its input
// (on a clean-looking mesh under weak noise that is right). On a triangulation of scanned points the
// narrow kernel's failure says nothing about the shape: every vertex is a noisy point, and the wide
// kernel's checked run is tried instead. A cube scanned from four directions under strong noise: its
// greedy triangles fail the narrow kernel's check; the wide kernel's run brings them closer to the clean
// mesh than the input and than the run that does not know its vertices are points.
TEST(ScanPairs, WhereTheNarrowKernelKeepsNothingAScanTakesTheWideOne) {
  Mesh clean, noisy;
  ASSERT_TRUE(bench::make_scan_pair(test::make_cube(8), scan_options(4, 96, 72, 0.3), clean, noisy));
  DenoiseOptions points, scanned;
  points.scanned = points.vertices_are_points = scanned.scanned = true;
  Mesh fallback = noisy, kept = noisy;
  const AutoReport a = denoise_auto(fallback, points);
  const AutoReport b = denoise_auto(kept, scanned);
  ASSERT_NE(b.reason.find("no feature-keeping iteration passed the result check"), std::string::npos) << b.reason;
  EXPECT_EQ(b.run.iterations, 0) << b.reason;
  EXPECT_EQ(a.mode, "smooth") << a.reason;
  EXPECT_NE(a.reason.find("the wide kernel instead"), std::string::npos) << a.reason;
  EXPECT_GT(a.run.iterations, 0) << a.reason;
  const double input = evaluate(noisy, &clean).msae_deg;
  EXPECT_LT(evaluate(fallback, &clean).msae_deg, evaluate(kept, &clean).msae_deg);
  EXPECT_LT(evaluate(fallback, &clean).msae_deg, input);
}

// Around a complete object too, a gap the closing leaves open is a region no view saw (no patch lies
// within the trim distance of the points), even with noisy points just inside its rim; it does not send
// the scan to Poisson, whose smooth surface lies farther from the object than the mesh through the
// points. The bumpy sphere from two views of 96 x 72 under weak noise.
TEST(MeshCloud, AGapNoViewSawKeepsGreedyProjectionAroundACompleteObject) {
  PointCloud c = merge_views(virtual_scan(bumpy_sphere(), scan_options(2, 96, 72, 0.1)));
  estimate_normals(c, NormalOptions{});
  PointCloud same = c;
  MeshingDecision d;
  const Mesh kept = mesh_cloud(c, MeshMethodOptions{}, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, measure_scale(c), &d);
  EXPECT_LT(decision_number(d, "one_sided_normals"), 0.9);
  ASSERT_EQ(d.method, MeshMethod::gp3) << d.reason;
  EXPECT_NE(d.reason.find("with points beside"), std::string::npos) << d.reason;
  EXPECT_NE(d.reason.find("the gaps left open lie farther than the trim distance from the points"), std::string::npos) << d.reason;
  MeshMethodOptions poisson;
  poisson.method = MeshMethod::poisson;
  const Mesh p = mesh_cloud(same, poisson, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, measure_scale(same), nullptr);
  const Mesh model = bumpy_sphere();
  EXPECT_LT(evaluate(kept, &model).ev_relative, evaluate(p, &model).ev_relative);
}

namespace {

// An organized single view of the bumpy sphere (240 x 180 pixels) meshed on its grid and cleaned, as
// the main job does with a depth frame.
Mesh organized_view(double noise) {
  PointCloud view = virtual_scan(bumpy_sphere(), scan_options(1, 240, 180, noise))[0];
  Mesh mesh = mesh_cloud(view, MeshMethodOptions{}, Gp3Options{}, OrganizedOptions{}, PoissonOptions{}, measure_scale(view));
  clean_mesh(mesh, CleanupOptions{});
  return mesh;
}

// `--auto` on `input` as scanned points, with the shipped rules and with `off`.
struct WithAndWithout {
  Mesh with, without;
  AutoReport a, b;
  WithAndWithout(const Mesh& input, const AutoRules& off) : with(input), without(input) {
    DenoiseOptions points;
    points.scanned = points.vertices_are_points = true;
    a = denoise_auto(with, points);
    b = denoise_auto(without, points, {}, off);
  }
};

}  // namespace

// Depth noise wider than the point spacing bends most edges by more than 45 degrees: the first wide
// iterations turn those hard creases into soft ones, so the soft share hardly falls while the surface is
// still rough, and the run stopped at its target after five iterations. Counting every bend over the soft
// creases' lower limit, the run goes on and ends far closer to the model. Under noise below the spacing
// the rule does not apply and the result is the same bytes.
TEST(ScanPairs, UnderNoiseWiderThanTheSpacingTheWideKernelRunsOnWhileItsBendsFall) {
  const Mesh model = bumpy_sphere();
  AutoRules off;
  off.points_bend_fall = false;
  const WithAndWithout r(organized_view(0.6), off);
  ASSERT_EQ(r.a.mode, "smooth") << r.a.reason;
  EXPECT_GT(r.a.ran_past_target, 0) << r.a.reason;
  EXPECT_GT(r.a.run.iterations, 2 * r.b.run.iterations) << r.a.reason << "\n" << r.b.reason;
  EXPECT_LT(nearest_face_normal_error(r.with, model), 0.5 * nearest_face_normal_error(r.without, model));
  const WithAndWithout moderate(organized_view(0.4), off);
  EXPECT_EQ(moderate.with.positions, moderate.without.positions);
}

// Under noise further past the spacing the bends fall slowly at first and the target comes after four
// iterations; while more edges than the probe's crease limit still bend by over 45 degrees the run goes on.
TEST(ScanPairs, UnderNoiseFarWiderThanTheSpacingTheWideKernelRunsOnWhileManyEdgesBendHard) {
  const Mesh model = bumpy_sphere();
  AutoRules off;
  off.points_hard_floor = false;
  const WithAndWithout r(organized_view(0.7), off);
  ASSERT_EQ(r.a.mode, "smooth") << r.a.reason;
  EXPECT_GT(r.a.run.iterations, 4 * r.b.run.iterations) << r.a.reason << "\n" << r.b.reason;
  EXPECT_LT(nearest_face_normal_error(r.with, model), 0.5 * nearest_face_normal_error(r.without, model));
}
