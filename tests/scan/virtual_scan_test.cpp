#include "scanmesh/combine_views.h"
#include "scanmesh/virtual_scan.h"

#include <gtest/gtest.h>

#include <cmath>

#include "helpers.h"
#include "scanmesh/closest_point.h"
#include "scanmesh/errors.h"
#include "scanmesh/parallel.h"

using namespace scanmesh;

TEST(VirtualScan, NoiseFreeHitsLieOnTheSurfaceAndFaceTheSensor) {
  const Mesh sphere = test::make_sphere(3);
  VirtualScanOptions o;
  o.noise = 0.0;
  o.width = 64;
  o.height = 48;
  const auto views = virtual_scan(sphere, o);
  ASSERT_EQ(views.size(), 6u);
  ClosestPointIndex index(sphere);
  std::size_t hits = 0;
  for (const auto& v : views) {
    EXPECT_TRUE(v.organized());
    EXPECT_EQ(v.size(), 64u * 48u);
    ASSERT_TRUE(v.sensor_origin.has_value());
    for (const auto& p : v.points) {
      if (!p.allFinite()) continue;
      ++hits;
      EXPECT_LT(index.closest(p).distance, 1e-9);
      // The first hit along the ray: on the half of the sphere facing the sensor.
      EXPECT_GT(p.dot(*v.sensor_origin - p), -1e-9);
    }
  }
  EXPECT_GT(hits, 6u * 64u * 48u / 8u);  // the bounding sphere spans 2/3 of the image width
}

TEST(VirtualScan, NoiseGrowsAlongTheRaysAndIsSeededAndThreadIndependent) {
  const Mesh cube = test::make_cube(6);
  VirtualScanOptions o;
  o.width = 80;
  o.height = 60;
  set_thread_count(1);
  const auto a = merge_views(virtual_scan(cube, o));
  set_thread_count(2);
  const auto b = merge_views(virtual_scan(cube, o));
  set_thread_count(0);
  EXPECT_EQ(a.points, b.points);
  o.seed = 2;
  const auto c = merge_views(virtual_scan(cube, o));
  EXPECT_NE(a.points, c.points);
  // Points are off the surface by about the requested noise (0.3 mean edges at the mean distance).
  ClosestPointIndex index(cube);
  double sum2 = 0.0;
  for (const auto& p : a.points) sum2 += std::pow(index.closest(p).distance, 2);
  const double rms = std::sqrt(sum2 / static_cast<double>(a.points.size()));
  EXPECT_GT(rms, 0.1 * 0.3 / 6.0);
  EXPECT_LT(rms, 2.0 * 0.3 / 6.0);
}

TEST(VirtualScan, DropoutsLeaveRoundSpotsEmptyAndTouchNothingElse) {
  const Mesh sphere = test::make_sphere(3);
  VirtualScanOptions o;
  o.views = 2;
  o.width = 64;
  o.height = 48;
  const auto full = virtual_scan(sphere, o);
  o.dropouts = 6;
  o.dropout_radius = 2.5;
  set_thread_count(1);
  const auto holed = virtual_scan(sphere, o);
  set_thread_count(2);
  const auto again = virtual_scan(sphere, o);
  set_thread_count(0);
  ASSERT_EQ(holed.size(), 2u);
  EXPECT_EQ(merge_views(holed).points, merge_views(again).points);  // the spots depend on the seed, not the threads
  std::size_t lost = 0;
  for (std::size_t v = 0; v < holed.size(); ++v) {
    ASSERT_EQ(holed[v].points.size(), full[v].points.size());
    std::size_t empty = 0;
    for (std::size_t k = 0; k < holed[v].points.size(); ++k) {
      const Vec3& p = holed[v].points[k];
      if (p.allFinite()) {
        EXPECT_EQ(p, full[v].points[k]);  // a pixel kept is the same measurement
      } else {
        ++empty;
        lost += full[v].points[k].allFinite() ? 1 : 0;
      }
    }
    // Six spots of radius 2.5 pixels: at most 6 x 29 pixels, less where they overlap or leave the image.
    std::size_t empty_before = 0;
    for (const Vec3& p : full[v].points) empty_before += p.allFinite() ? 0 : 1;
    EXPECT_LE(empty - empty_before, 6u * 29u);
  }
  EXPECT_GT(lost, 0u);  // the object fills two thirds of the image: some spots fall on it
}

TEST(VirtualScan, RejectsBadOptions) {
  VirtualScanOptions o;
  o.views = 0;
  EXPECT_THROW(virtual_scan(test::make_cube(2), o), UsageError);
  EXPECT_THROW(virtual_scan(Mesh{}, VirtualScanOptions{}), InputError);
}
