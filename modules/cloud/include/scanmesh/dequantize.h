#pragma once
// Quantized depth: structured-light and stereo cameras (Kinect and its kin) store depth in a few hundred
// levels, so a slanted wall becomes a staircase of flat treads with steps of centimetres. Meshed as it is,
// the treads are exactly flat (a denoiser takes them for a clean tessellation) and every step stays.
// Detection: an organized cloud whose depths take few distinct values and whose neighbouring pixels very
// often share one exactly. Dequantization turns each staircase back into a ramp: along every row and
// every column, the depth runs through the centres of neighbouring treads one level apart (larger jumps
// are real edges and stay), rows and columns averaged, and each point moves along its sensor ray, never
// by more than half a step. The options struct is the schema of the cloud.dequantize stage.
#include <cstddef>

#include "scanmesh/point_cloud.h"
#include "scanmesh/schema.h"

namespace scanmesh {

enum class DequantizeMode { automatic, always, never };

struct DequantizeOptions {
  DequantizeMode mode = DequantizeMode::automatic;
  static const Schema<DequantizeOptions>& schema() {
    static const Schema<DequantizeOptions> s = Schema<DequantizeOptions>().choice(
        "dequantize", &DequantizeOptions::mode,
        {{"auto", DequantizeMode::automatic}, {"always", DequantizeMode::always}, {"never", DequantizeMode::never}},
        "auto: dequantize organized clouds whose depth is quantized (few distinct depths, neighbouring pixels often "
        "exactly equal); always: every organized cloud; never: leave the depths as they are.");
    return s;
  }
};

/// What was measured and done.
struct QuantizationReport {
  bool organized = false;
  std::size_t valid_points = 0;
  std::size_t distinct_depths = 0;   ///< distinct depth values (along the sensor's viewing axis)
  double equal_neighbours = 0.0;     ///< share of horizontally neighbouring valid pixels with exactly equal depth
  double median_step = 0.0;          ///< median gap between consecutive distinct depths, scene units
  bool quantized = false;            ///< the verdict of the detection
  bool applied = false;              ///< the depths were changed
  std::size_t moved = 0;             ///< points that moved
};

/// Measures whether the cloud's depth is quantized (organized clouds only; others are never quantized).
QuantizationReport analyse_depth_quantization(const PointCloud& cloud);

/// Detects and, as the options say, removes depth quantization in place. Deterministic.
QuantizationReport dequantize_depth(PointCloud& cloud, const DequantizeOptions& options);

}  // namespace scanmesh
