#pragma once
// A virtual depth scanner: ray-casts a clean mesh (VTK's static cell locator) from several viewpoints and
// adds depth noise along each ray that grows with depth squared, as a structured-light/ToF sensor does.
// It gives scans with known ground truth. The options struct is the schema of the scan.virtual stage.
#include <cstdint>
#include <vector>

#include "scanmesh/mesh.h"
#include "scanmesh/point_cloud.h"

namespace scanmesh {

struct VirtualScanOptions {
  int views = 6;             ///< viewpoints spread evenly over a sphere around the mesh (Fibonacci lattice)
  int width = 320;           ///< image columns per view
  int height = 240;          ///< image rows per view
  double fov_deg = 40.0;     ///< horizontal field of view; the object fills about two thirds of it
  /// Depth noise standard deviation at the mean viewing distance, in mean edge lengths of the mesh; it
  /// scales with (depth / mean depth)^2 like a Kinect's.
  double noise = 0.3;
  std::uint64_t seed = 1;
};

/// One organized cloud per view (width x height, NaN where the ray misses), each with its sensor origin
/// and orientation. Deterministic for a seed, whatever the thread count.
std::vector<PointCloud> virtual_scan(const Mesh& mesh, const VirtualScanOptions& options);

/// All finite points of the views in one unorganized cloud; each point's normal is the unit direction
/// towards the sensor that saw it (merging loses the viewpoints; this keeps what orientation needs).
PointCloud merge_scans(const std::vector<PointCloud>& views);

}  // namespace scanmesh
