#include "scanmesh/dequantize.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace scanmesh;

namespace {

// A depth camera at the origin looking along +z at `depth(u, v)`, its depth rounded to `step`.
template <class F>
PointCloud depth_frame(int w, int h, double step, F depth, std::vector<double>* truth = nullptr) {
  PointCloud c;
  c.width = w;
  c.height = h;
  c.sensor_origin = Vec3::Zero();
  const double f = 1.0 / w;  // pixel pitch (radians, small-angle)
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const double z = depth(u, v);
      if (truth) truth->push_back(z);
      const double q = step > 0 ? step * std::round(z / step) : z;
      c.points.emplace_back((u - w / 2) * f * q, (v - h / 2) * f * q, q);
    }
  return c;
}

}  // namespace

TEST(Dequantize, AQuantizedSlantedWallBecomesARampAgain) {
  const double step = 0.01;
  std::vector<double> truth;
  PointCloud c = depth_frame(160, 120, step, [](int u, int) { return 1.0 + 0.002 * u; }, &truth);
  const QuantizationReport before = analyse_depth_quantization(c);
  EXPECT_TRUE(before.quantized);
  EXPECT_LE(before.distinct_depths, 40u);
  EXPECT_NEAR(before.median_step, step, 1e-9);
  double err_before = 0.0, err_after = 0.0;
  for (std::size_t i = 0; i < c.size(); ++i) err_before += std::abs(c.points[i].z() - truth[i]);
  const QuantizationReport r = dequantize_depth(c, {});
  EXPECT_TRUE(r.applied);
  for (std::size_t i = 0; i < c.size(); ++i) {
    err_after += std::abs(c.points[i].z() - truth[i]);
    // Along its ray, never more than half a step from the measured level.
    EXPECT_LE(std::abs(c.points[i].z() - step * std::round(truth[i] / step)), 0.5 * step + 1e-12);
  }
  EXPECT_LT(err_after, 0.25 * err_before) << "mean error " << err_before / c.size() << " -> " << err_after / c.size();
}

TEST(Dequantize, RealDepthJumpsStayAndContinuousDepthIsLeftAlone) {
  // Two slanted walls 10 steps apart: the jump between them is an edge, not a staircase.
  PointCloud c = depth_frame(120, 80, 0.01, [](int u, int v) { return 1.0 + 0.0011 * v + (u < 60 ? 0.0 : 0.1); });
  dequantize_depth(c, DequantizeOptions{DequantizeMode::always});
  for (int v = 0; v < 80; ++v) {  // the jump is still 10 steps, not smoothed into a ramp
    const double jump = c.points[v * 120 + 60].z() - c.points[v * 120 + 59].z();
    EXPECT_NEAR(jump, 0.1, 0.01) << "row " << v;
  }
  // A laser scan's continuous depths are not quantized: auto leaves them as they are.
  PointCloud smooth = depth_frame(120, 80, 0.0, [](int u, int v) { return 1.0 + 0.0013 * u + 0.0007 * v + 1e-5 * std::sin(u * v); });
  const PointCloud copy = smooth;
  const QuantizationReport r = dequantize_depth(smooth, {});
  EXPECT_FALSE(r.quantized);
  EXPECT_FALSE(r.applied);
  EXPECT_EQ(smooth.points, copy.points);
}

TEST(Dequantize, UnorganizedCloudsAreNeverTouched) {
  PointCloud c;
  for (int i = 0; i < 500; ++i) c.points.emplace_back(i * 0.01, 0.0, std::round(i / 50.0));
  c.width = static_cast<int>(c.size());
  const QuantizationReport r = dequantize_depth(c, DequantizeOptions{DequantizeMode::always});
  EXPECT_FALSE(r.organized);
  EXPECT_FALSE(r.applied);
}
