#pragma once
// Cloud clean-up stages (PCL inside): crop box, voxel grid, statistical and radius outlier removal,
// normal estimation, moving least squares. Each takes an options struct that is also the schema of its
// pipeline stage (cloud.crop, cloud.voxel, cloud.outliers, cloud.normals, cloud.mls).
#include <string>

#include "scanmesh/length.h"
#include "scanmesh/schema.h"
#include "scanmesh/neighbourhoods.h"
#include "scanmesh/point_cloud.h"

namespace scanmesh {


struct CropOptions {
  Vec3 min = Vec3::Constant(-1e300);
  Vec3 max = Vec3::Constant(1e300);
  static const Schema<CropOptions>& schema() {
    static const Schema<CropOptions> s = Schema<CropOptions>()
        .vec3("crop_min", &CropOptions::min, "scene units", "Lowest corner of the box whose points are kept.")
        .vec3("crop_max", &CropOptions::max, "scene units", "Highest corner of the box whose points are kept.");
    return s;
  }
};
/// Keeps the points inside the box (componentwise min <= p <= max); the result is unorganized.
void crop(PointCloud& cloud, const CropOptions& options);

struct VoxelOptions {
  Length leaf = Length::spacings(0.0);
  int max_points = 0;
  static const Schema<VoxelOptions>& schema() {
    static const Schema<VoxelOptions> s =
        Schema<VoxelOptions>()
            .length("voxel_leaf", &VoxelOptions::leaf, at_least(0),
                    "Voxel-grid edge: one point (the centroid) per occupied voxel; 0 keeps every point.")
            .integer("voxel_max_points", &VoxelOptions::max_points, closed(0, 2000000000), "count",
                     "Most points to keep: an unorganized cloud with more gets the smallest voxel edge (at least voxel_leaf, "
                     "within 2%) that brings it to this count, found from its point spacing. Organized clouds are left whole "
                     "(their meshing is linear in the pixels). 0 = no limit.");
    return s;
  }
};
/// What voxel_downsample did: point counts before and after, and the voxel edge it used (0: none).
struct VoxelReport {
  std::size_t before = 0, after = 0;
  double leaf = 0.0;
  bool limit_skipped_organized = false;  ///< over max_points but organized: left whole
};
/// One point per occupied voxel (the centroid; normals and colours averaged). Deterministic.
VoxelReport voxel_downsample(PointCloud& cloud, const VoxelOptions& options, const CloudScale& scale);

struct OutlierOptions {
  int neighbours = 16;
  double std_ratio = 3.0;
  Length radius = Length::spacings(0.0);
  int min_neighbours = 3;
  static const Schema<OutlierOptions>& schema() {
    static const Schema<OutlierOptions> s =
        Schema<OutlierOptions>()
            .integer("outlier_neighbours", &OutlierOptions::neighbours, closed(1, 1000), "count",
                     "Neighbours whose mean distance the statistical outlier test compares.")
            .number("outlier_std_ratio", &OutlierOptions::std_ratio, closed(0, 100), "standard deviations",
                    "Remove points whose mean neighbour distance exceeds the mean by this many standard deviations; 0 = off.")
            .length("outlier_radius", &OutlierOptions::radius, at_least(0),
                    "Radius filter: a point with fewer than outlier_min_neighbours within this distance is removed; 0 = off.")
            .integer("outlier_min_neighbours", &OutlierOptions::min_neighbours, closed(1, 1000), "count",
                     "Radius filter: neighbours a point needs within outlier_radius to stay.");
    return s;
  }
};
/// Statistical (and, if radius > 0, radius) outlier removal; organized clouds keep their grid (removed
/// points become NaN holes).
void remove_outliers(PointCloud& cloud, const OutlierOptions& options, const CloudScale& scale);

struct NormalOptions {
  int neighbours = 20;
  bool orient = true;
  bool keep = false;
  static const Schema<NormalOptions>& schema() {
    static const Schema<NormalOptions> s =
        Schema<NormalOptions>()
            .integer("normal_neighbours", &NormalOptions::neighbours, closed(3, 1000), "count",
                     "Nearest neighbours whose least-squares plane gives a point's normal.")
            .flag("orient_normals", &NormalOptions::orient,
                  "Orient normals: towards the sensor when the file knows it, else like normals the file has, else "
                  "consistently over the neighbour graph, outwards from the highest point.")
            .flag("keep_normals", &NormalOptions::keep, "Use the normals stored in the file, when it has them, instead of estimating.");
    return s;
  }
};
/// Estimates unit normals (PCL NormalEstimationOMP; deterministic). Points without enough neighbours
/// get the normal of their nearest neighbour that has one. With options.keep and normals in the cloud,
/// nothing changes.
void estimate_normals(PointCloud& cloud, const NormalOptions& options);

struct MlsOptions {
  Length radius = Length::spacings(4.0);
  int polynomial_order = 2;
  static const Schema<MlsOptions>& schema() {
    static const Schema<MlsOptions> s = Schema<MlsOptions>()
        .length("mls_radius", &MlsOptions::radius, at_least(0), "Moving-least-squares neighbourhood radius; 0 = off.")
        .integer("mls_order", &MlsOptions::polynomial_order, closed(1, 4), "degree", "Degree of the local polynomial surface.");
    return s;
  }
};
/// Moving-least-squares projection of the points (PCL MovingLeastSquares), keeping their order.
void smooth_mls(PointCloud& cloud, const MlsOptions& options, const CloudScale& scale);

}  // namespace scanmesh
