#pragma once
// Point cloud -> triangle mesh with PCL: greedy projection triangulation (keeps the measured points as
// vertices, so the denoiser sees the real noise), organized fast mesh (for organized frames and range
// grids) and Poisson reconstruction (watertight option). Options structs are the schemas of the
// mesh.gp3, mesh.organized and mesh.poisson pipeline stages.
#include "scanmesh/clean_cloud.h"
#include "scanmesh/length.h"
#include "scanmesh/mesh.h"
#include "scanmesh/point_cloud.h"

namespace scanmesh {

struct Gp3Options {
  Length radius = Length::spacings(5.0);  ///< largest edge a triangle may have
  double mu = 3.0;                        ///< max edge relative to the local point spacing
  int max_neighbours = 100;
  double max_surface_angle_deg = 45.0;    ///< neighbours whose normals deviate more are not connected
  double min_angle_deg = 10.0;
  double max_angle_deg = 120.0;
};
/// Needs normals (estimate_normals). Vertices are the cloud's finite points in their order.
Mesh triangulate_gp3(const PointCloud& cloud, const Gp3Options& options, const CloudScale& scale);

struct OrganizedOptions {
  Length max_edge = Length::spacings(6.0);  ///< triangles with a longer edge are not made (depth jumps)
  double max_view_angle_deg = 80.0;         ///< drop triangles seen this obliquely from the sensor
};
/// Triangulates an organized cloud (width x height grid with NaN holes) pixel by pixel.
Mesh triangulate_organized(const PointCloud& cloud, const OrganizedOptions& options, const CloudScale& scale);

struct PoissonOptions {
  int depth = 8;  ///< octree depth (detail vs. time and memory)
  /// Without `watertight`, faces with a vertex farther than this from every input point are removed
  /// (Poisson closes holes and the open sides of a scan with invented surface).
  Length trim_distance = Length::spacings(3.0);
  bool watertight = false;
};
/// Needs oriented normals. Creates new vertices (smooth surface), unlike gp3 and organized.
Mesh triangulate_poisson(const PointCloud& cloud, const PoissonOptions& options, const CloudScale& scale);

}  // namespace scanmesh
