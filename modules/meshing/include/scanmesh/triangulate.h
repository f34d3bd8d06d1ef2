#pragma once
// Point cloud -> triangle mesh with PCL: greedy projection triangulation (keeps the measured points as
// vertices, so the denoiser sees the real noise), organized fast mesh (for organized frames and range
// grids) and Poisson reconstruction (watertight option). Options structs are the schemas of the
// mesh.gp3, mesh.organized and mesh.poisson pipeline stages.
#include "scanmesh/clean_cloud.h"
#include "scanmesh/length.h"
#include "scanmesh/mesh.h"
#include "scanmesh/point_cloud.h"
#include "scanmesh/schema.h"

namespace scanmesh {

struct Gp3Options {
  Length radius = Length::spacings(5.0);
  double mu = 3.0;
  int max_neighbours = 100;
  double max_surface_angle_deg = 45.0;
  double min_angle_deg = 10.0;
  double max_angle_deg = 120.0;
  bool flips = true;
  static const Schema<Gp3Options>& schema() {
    static const Schema<Gp3Options> s =
        Schema<Gp3Options>()
            .length("gp3_radius", &Gp3Options::radius, open_closed(0, 1e300), "Greedy projection: the longest edge a triangle may have.")
            .number("gp3_mu", &Gp3Options::mu, closed(1, 10), "x local spacing",
                    "Greedy projection: longest edge relative to the local point spacing.")
            .integer("gp3_max_neighbours", &Gp3Options::max_neighbours, closed(10, 10000), "count",
                     "Greedy projection: neighbours considered per point.")
            .number("gp3_max_surface_angle", &Gp3Options::max_surface_angle_deg, closed(1, 180), "degrees",
                    "Greedy projection: points whose normals differ more are not connected.")
            .number("gp3_min_angle", &Gp3Options::min_angle_deg, closed(0, 60), "degrees", "Greedy projection: smallest triangle angle.")
            .number("gp3_max_angle", &Gp3Options::max_angle_deg, closed(60, 180), "degrees", "Greedy projection: largest triangle angle.")
            .flag("gp3_flips", &Gp3Options::flips,
                  "Greedy projection: then flip edges towards a Delaunay triangulation of the same points (rounder "
                  "triangles, no point moves; a flip that would fold, or bend the pair more than it was and than 30 "
                  "degrees, is not made).");
    return s;
  }
};
/// Needs normals (estimate_normals). Vertices are the cloud's finite points in their order.
Mesh triangulate_gp3(const PointCloud& cloud, const Gp3Options& options, const CloudScale& scale);

struct OrganizedOptions {
  Length max_edge = Length::spacings(6.0);
  double max_view_angle_deg = 80.0;
  static const Schema<OrganizedOptions>& schema() {
    static const Schema<OrganizedOptions> s =
        Schema<OrganizedOptions>()
            .length("max_edge", &OrganizedOptions::max_edge, open_closed(0, 1e300),
                    "Organized meshing: triangles with a longer edge are not made (depth jumps stay open).")
            .number("max_view_angle", &OrganizedOptions::max_view_angle_deg, closed(1, 90), "degrees",
                    "Organized meshing: triangles seen more obliquely from the sensor are dropped.");
    return s;
  }
};
/// Triangulates an organized cloud (width x height grid with NaN holes) pixel by pixel. A max_edge in
/// spacings is relative to the pixel footprint at each point's range from the sensor.
Mesh triangulate_organized(const PointCloud& cloud, const OrganizedOptions& options, const CloudScale& scale);

struct PoissonOptions {
  int depth = 0;
  Length trim_distance = Length::spacings(3.0);
  bool watertight = false;
  static const Schema<PoissonOptions>& schema() {
    static const Schema<PoissonOptions> s =
        Schema<PoissonOptions>()
            .integer("poisson_depth", &PoissonOptions::depth, closed(0, 12), "octree levels",
                     "Poisson: detail against time and memory; 0 = cells about one point spacing wide (5 to 10 levels).")
            .length("poisson_trim", &PoissonOptions::trim_distance, at_least(0),
                    "Poisson: faces with a vertex farther than this from every input point are removed (invented surface).")
            .flag("watertight", &PoissonOptions::watertight, "Poisson: keep the closed surface, do not trim.");
    return s;
  }
};
/// Needs oriented normals. Creates new vertices (smooth surface), unlike gp3 and organized. Screened
/// Poisson reconstruction (Kazhdan and Hoppe 2013, PCL's implementation), trimmed back to the data.
Mesh triangulate_poisson(const PointCloud& cloud, const PoissonOptions& options, const CloudScale& scale);

/// The angle one pixel of an organized cloud spans, seen from `eye`: the median over grid neighbours of
/// their distance over their range (0 if it cannot be measured).
double pixel_pitch(const PointCloud& cloud, const Vec3& eye);

/// The octree depth poisson_depth 0 stands for: cells about one point spacing wide, 5 to 10 levels.
int poisson_depth_for(const PointCloud& cloud, const CloudScale& scale);

}  // namespace scanmesh
