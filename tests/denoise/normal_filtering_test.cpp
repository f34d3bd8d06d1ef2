#include "scanmesh/normal_filtering.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include "helpers.h"
#include "scanmesh/vertex_update.h"

using namespace scanmesh;

TEST(NormalFiltering, RobustWeights) {
  EXPECT_DOUBLE_EQ(robust_weight(RobustEstimator::tukey, 0.0, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(robust_weight(RobustEstimator::tukey, 0.25, 0.5), 0.5 * 0.75 * 0.75);
  EXPECT_DOUBLE_EQ(robust_weight(RobustEstimator::tukey, 0.51, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(robust_weight(RobustEstimator::gaussian, 0.5, 0.5), std::exp(-0.5));
  EXPECT_DOUBLE_EQ(robust_weight(RobustEstimator::huber, 1.0, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(robust_weight(RobustEstimator::lorentzian, 0.5, 0.5), 1.0 / 1.5);
}

TEST(NormalFiltering, TukeyDoesNotMixAcrossARightAngle) {
  // Cube edges: |n_i - n_j| = sqrt(2) > sigma_s, so filtered normals of a clean cube are exact.
  const Mesh cube = test::make_cube(4);
  const Topology t = build_topology(cube);
  FaceGeometry g;
  compute_face_geometry(cube.positions, cube.faces, g);
  const double ca = mean_centroid_distance(cube, t, g);
  const Adjacency nbh = face_neighbourhoods(t, g, 2.0 * ca, NeighbourhoodKind::ball, max_neighbourhood_size(2.0));
  std::vector<Vec3> filtered;
  filter_face_normals(g, nbh, ca, 0.5, RobustEstimator::tukey, filtered);
  for (std::size_t f = 0; f < cube.num_faces(); ++f) EXPECT_LT((filtered[f] - g.normals[f]).norm(), 1e-12);
  // A Gaussian kernel with a wide sigma does mix them.
  filter_face_normals(g, nbh, ca, 2.0, RobustEstimator::gaussian, filtered);
  double mixed = 0.0;
  for (std::size_t f = 0; f < cube.num_faces(); ++f) mixed = std::max(mixed, (filtered[f] - g.normals[f]).norm());
  EXPECT_GT(mixed, 0.1);
}

TEST(NormalFiltering, ConnectedBallIsASubsetOfTheBall) {
  // Two parallel sheets 0.05 apart: the ball mixes them, the connected ball does not.
  Mesh m = test::make_grid(6, 0.1);
  const int n = static_cast<int>(m.num_vertices());
  Mesh top = test::make_grid(6, 0.1);
  for (auto p : top.positions) m.positions.push_back(p + Vec3(0, 0, 0.05));
  for (auto f : top.faces) m.faces.push_back({f[0] + n, f[2] + n, f[1] + n});
  const Topology t = build_topology(m);
  FaceGeometry g;
  compute_face_geometry(m.positions, m.faces, g);
  const double ca = mean_centroid_distance(m, t, g);
  const Adjacency ball = face_neighbourhoods(t, g, 2.0 * ca, NeighbourhoodKind::ball, max_neighbourhood_size(2.0));
  const Adjacency conn = face_neighbourhoods(t, g, 2.0 * ca, NeighbourhoodKind::connected_ball, max_neighbourhood_size(2.0));
  const std::size_t half = m.num_faces() / 2;
  std::size_t crossing_ball = 0, crossing_conn = 0;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    for (const int* j = ball.begin(f); j != ball.end(f); ++j) crossing_ball += (static_cast<std::size_t>(*j) < half) != (f < half);
    for (const int* j = conn.begin(f); j != conn.end(f); ++j) {
      crossing_conn += (static_cast<std::size_t>(*j) < half) != (f < half);
      EXPECT_TRUE(std::binary_search(ball.begin(f), ball.end(f), *j));
    }
  }
  EXPECT_GT(crossing_ball, 0u);
  EXPECT_EQ(crossing_conn, 0u);
}

namespace {

// The filter as the paper writes it, in double precision one neighbour at a time with std::exp: what the
// eight-lane single-precision kernel must agree with to single precision.
std::vector<Vec3> reference_tukey(const FaceGeometry& g, const Adjacency& nbh, double sigma_c, double sigma_s) {
  std::vector<Vec3> out(g.normals.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    Vec3 sum = Vec3::Zero();
    for (const int* j = nbh.begin(i); j != nbh.end(i); ++j) {
      const double d = (g.centroids[i] - g.centroids[*j]).norm();
      sum += g.areas[*j] * std::exp(-d * d / (2 * sigma_c * sigma_c)) *
             robust_weight(RobustEstimator::tukey, (g.normals[i] - g.normals[*j]).norm(), sigma_s) * g.normals[*j];
    }
    out[i] = sum.norm() > 0 ? Vec3(sum.normalized()) : g.normals[i];
  }
  return out;
}

}  // namespace

TEST(NormalFiltering, TheEightLaneKernelMatchesTheFormulaOnEveryInstructionSet) {
  // A noisy sphere: neighbourhoods of every length mod 8, normals on both sides of the Tukey cut-off.
  Mesh m = test::make_sphere(4);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.02);  // about 0.3 mean edges
  for (auto& p : m.positions) p += Vec3(noise(rng), noise(rng), noise(rng));
  const Topology t = build_topology(m);
  FaceGeometry g;
  compute_face_geometry(m.positions, m.faces, g);
  const double ca = mean_centroid_distance(m, t, g);
  // Radius 4 c_a: closeness arguments down to -8, where the polynomial e^x is least exact.
  const Adjacency nbh = face_neighbourhoods(t, g, 4.0 * ca, NeighbourhoodKind::ball, max_neighbourhood_size(4.0));
  const std::vector<Vec3> want = reference_tukey(g, nbh, ca, 0.5);
  std::vector<Vec3> best, sse2;
  set_filter_isa(FilterIsa::best);
  filter_face_normals(g, nbh, ca, 0.5, RobustEstimator::tukey, best);
  set_filter_isa(FilterIsa::sse2);
  filter_face_normals(g, nbh, ca, 0.5, RobustEstimator::tukey, sse2);
  set_filter_isa(FilterIsa::best);
  double worst = 0.0;
  std::size_t differ = 0;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    worst = std::max(worst, (best[f] - want[f]).norm());
    differ += best[f] != sse2[f];
  }
  EXPECT_LT(worst, 1e-6);  // radians; a wrong weight or a dropped lane shows as 1e-3 and more
  EXPECT_EQ(differ, 0u) << "AVX2 and SSE2 must give the same bits";
  // The packed table the denoiser holds gives the same bits, with every estimator.
  const PackedRows packed = packed_face_neighbourhoods(t, g, 4.0 * ca, NeighbourhoodKind::ball, max_neighbourhood_size(4.0));
  EXPECT_EQ(packed.entries(), nbh.indices.size());
  for (RobustEstimator e : {RobustEstimator::tukey, RobustEstimator::gaussian, RobustEstimator::huber, RobustEstimator::lorentzian}) {
    std::vector<Vec3> plain, from_packed;
    filter_face_normals(g, nbh, ca, 0.5, e, plain);
    filter_face_normals(g, packed, ca, 0.5, e, from_packed);
    EXPECT_EQ(plain, from_packed) << to_string(e);
  }
  // And the filter did something: the noisy normals moved.
  double moved = 0.0;
  for (std::size_t f = 0; f < m.num_faces(); ++f) moved = std::max(moved, (best[f] - g.normals[f]).norm());
  EXPECT_GT(moved, 0.05);
}

// The denoiser's iterations keep no centroid table: the kernel and the vertex update compute each centroid
// from the positions. That must give the same bits as reading the table.
TEST(NormalFiltering, CentroidsFromThePositionsGiveTheSameBits) {
  Mesh m = test::make_sphere(3);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  for (auto& p : m.positions) p += Vec3(noise(rng), noise(rng), noise(rng)) + Vec3(1e3, -2e3, 5e2);  // far from the origin
  const Topology t = build_topology(m);
  FaceGeometry full, lean;
  compute_face_geometry(m.positions, m.faces, full);
  compute_face_geometry(m.positions, m.faces, lean, false);
  ASSERT_TRUE(lean.centroids.empty());
  EXPECT_EQ(full.normals, lean.normals);
  const double ca = mean_centroid_distance(m, t, full);
  const PackedRows nbh = packed_face_neighbourhoods(t, full, 3.0 * ca, NeighbourhoodKind::ball, max_neighbourhood_size(3.0));
  std::vector<Vec3> from_table, from_positions;
  filter_face_normals(full, nbh, ca, 0.5, RobustEstimator::tukey, from_table);
  FilterWork work;
  work.positions = &m.positions;
  work.faces = &m.faces;
  filter_face_normals(lean, nbh, ca, 0.5, RobustEstimator::tukey, from_positions, nullptr, &work);
  EXPECT_EQ(from_table, from_positions);
  // Without positions to compute them from, a lean geometry is a programming error, not a wrong result.
  EXPECT_THROW(filter_face_normals(lean, nbh, ca, 0.5, RobustEstimator::tukey, from_positions), std::logic_error);
  EXPECT_THROW(filter_face_normals(lean, nbh, ca, 0.5, RobustEstimator::gaussian, from_positions, nullptr, &work), std::logic_error);

  Topology vt = build_topology(m);
  const PackedRows fidelity = PackedRows::from(fidelity_neighbours(m, vt));
  std::vector<Vec3> a, b;
  VertexUpdateTerms terms;
  terms.lambda = 0.2;
  update_vertices(m.positions, t, fidelity, full, from_table, terms, a);
  update_vertices(m.positions, t, fidelity, lean, from_table, terms, b, &m.faces);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, m.positions);  // the update did move the vertices
}

// The iterations' face pass (refresh_faces) does in one read of the corners what compute_face_geometry,
// the kernel's own packing and mark_new_slivers did in three: the same bits, the same flags.
TEST(NormalFiltering, OneFacePassGivesTheSameBitsAsThree) {
  Mesh input = test::make_zippered_cylinder();  // a tessellation with slivers of its own
  for (auto& p : input.positions) p += Vec3(1e3, -2e3, 5e2);  // far from the origin
  std::vector<Vec3> moved = input.positions;
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (auto& p : moved) p += Vec3(noise(rng), noise(rng), noise(rng));  // makes new slivers and unmakes some
  const Topology t = build_topology(input);

  FaceGeometry three;
  compute_face_geometry(moved, input.faces, three, false);
  std::vector<std::uint8_t> flags_three, flags_one;
  const std::size_t count_three = mark_new_slivers(moved, input.positions, input.faces, 3.0, flags_three);
  ASSERT_GT(count_three, 0u);
  ASSERT_LT(count_three, input.faces.size());

  FaceGeometry one;
  FilterWork work;
  work.positions = &moved;
  work.faces = &input.faces;
  EXPECT_EQ(refresh_faces(moved, input.positions, input.faces, 3.0, one, work, flags_one), count_three);
  EXPECT_EQ(flags_one, flags_three);
  EXPECT_EQ(one.normals, three.normals);
  EXPECT_EQ(one.areas, three.areas);
  EXPECT_TRUE(one.centroids.empty());
  EXPECT_TRUE(work.records_ready);

  // Filtering from the refreshed records gives what filtering with its own packing gives, and uses them once.
  FaceGeometry g;
  compute_face_geometry(moved, input.faces, g);
  const double ca = mean_centroid_distance(input, t, g);
  const PackedRows nbh = packed_face_neighbourhoods(t, g, 3.0 * ca, NeighbourhoodKind::ball, max_neighbourhood_size(3.0));
  std::vector<Vec3> from_refresh, from_packing;
  filter_face_normals(one, nbh, ca, 0.5, RobustEstimator::tukey, from_refresh, nullptr, &work);
  EXPECT_FALSE(work.records_ready);
  FilterWork fresh;
  fresh.positions = &moved;
  fresh.faces = &input.faces;
  filter_face_normals(three, nbh, ca, 0.5, RobustEstimator::tukey, from_packing, nullptr, &fresh);
  EXPECT_EQ(from_refresh, from_packing);
  EXPECT_NE(from_refresh, three.normals);  // the filter did change the normals

  // Without a sliver limit no flags are computed.
  std::vector<std::uint8_t> none;
  EXPECT_EQ(refresh_faces(moved, input.positions, input.faces, 0.0, one, work, none), 0u);
  EXPECT_TRUE(none.empty());
}
