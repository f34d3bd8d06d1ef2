#pragma once
// A virtual depth scanner: ray-casts a clean mesh (VTK's static cell locator) from several viewpoints and
// adds depth noise along each ray that grows with depth squared, as a structured-light/ToF sensor does.
// It gives scans with known ground truth. The options struct is the schema of the scan.virtual stage.
#include <cstdint>
#include <vector>

#include "scanmesh/mesh.h"
#include "scanmesh/point_cloud.h"
#include "scanmesh/schema.h"

namespace scanmesh {

struct VirtualScanOptions {
  int views = 6;
  int width = 320;
  int height = 240;
  double fov_deg = 40.0;
  double noise = 0.3;
  int dropouts = 0;
  double dropout_radius = 3.0;
  std::uint64_t seed = 1;
  static const Schema<VirtualScanOptions>& schema() {
    static const Schema<VirtualScanOptions> s =
        Schema<VirtualScanOptions>()
            .integer("views", &VirtualScanOptions::views, closed(1, 1000), "count",
                     "Viewpoints spread evenly over a sphere around the mesh (Fibonacci lattice).")
            .integer("width", &VirtualScanOptions::width, closed(2, 10000), "pixels", "Image columns per view.")
            .integer("height", &VirtualScanOptions::height, closed(2, 10000), "pixels", "Image rows per view.")
            .number("fov", &VirtualScanOptions::fov_deg, closed(1, 170), "degrees",
                    "Horizontal field of view; the object fills about two thirds of it.")
            .number("scan_noise", &VirtualScanOptions::noise, closed(0, 100), "x mean edge",
                    "Depth noise deviation at the mean viewing distance, growing with depth squared like a Kinect's.")
            .integer("dropouts", &VirtualScanOptions::dropouts, closed(0, 100000), "count",
                     "Round spots per view where the sensor returns nothing (a dark, shiny or grazing patch), "
                     "centred at random over the image.")
            .number("dropout_radius", &VirtualScanOptions::dropout_radius, closed(0.5, 10000), "pixels", "Radius of each dropout spot.")
            .seed("scan_seed", &VirtualScanOptions::seed, "Same seed, same scan, whatever the thread count.");
    return s;
  }
};

/// One organized cloud per view (width x height, NaN where the ray misses), each with its sensor origin
/// and orientation. Deterministic for a seed, whatever the thread count.
std::vector<PointCloud> virtual_scan(const Mesh& mesh, const VirtualScanOptions& options);

/// (merge_views in combine_views.h makes one cloud of the views, each point keeping the direction to the
/// sensor that saw it as an orientation hint.)

}  // namespace scanmesh
