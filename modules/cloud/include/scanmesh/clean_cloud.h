#pragma once
// Cloud clean-up stages (PCL inside): crop box, voxel grid, statistical and radius outlier removal,
// normal estimation, moving least squares. Each takes an options struct that is also the schema of its
// pipeline stage (cloud.crop, cloud.voxel, cloud.outliers, cloud.normals, cloud.mls).
#include <string>

#include "scanmesh/length.h"
#include "scanmesh/point_cloud.h"

namespace scanmesh {

/// Scale of a cloud: mean nearest-neighbour spacing (FLANN) and bounding-box diagonal of its finite points.
struct CloudScale {
  double spacing = 0.0;
  double diagonal = 0.0;
};
CloudScale measure_scale(const PointCloud& cloud);

struct CropOptions {
  Vec3 min = Vec3::Constant(-1e300);  ///< keep points with min <= p <= max (componentwise)
  Vec3 max = Vec3::Constant(1e300);
};
/// Keeps the points inside the box; the result is unorganized.
void crop(PointCloud& cloud, const CropOptions& options);

struct VoxelOptions {
  Length leaf = Length::spacings(0.0);  ///< voxel edge; 0 = off
};
/// One point per occupied voxel (the centroid; normals and colours averaged). Deterministic.
void voxel_downsample(PointCloud& cloud, const VoxelOptions& options, const CloudScale& scale);

struct OutlierOptions {
  int neighbours = 16;              ///< statistical: k nearest neighbours
  double std_ratio = 3.0;           ///< statistical: remove points whose mean k-distance exceeds mean + ratio * std
  Length radius = Length::spacings(0.0);  ///< radius filter: 0 = off
  int min_neighbours = 3;           ///< radius filter: fewer neighbours within the radius -> removed
};
/// Statistical (and, if radius > 0, radius) outlier removal; organized clouds keep their grid (removed
/// points become NaN holes).
void remove_outliers(PointCloud& cloud, const OutlierOptions& options, const CloudScale& scale);

struct NormalOptions {
  int neighbours = 20;  ///< k nearest neighbours for the PCA plane
  /// Orientation: towards the sensor when the cloud knows it; else agreeing with normals the cloud already
  /// has (e.g. from the scanner); else propagated consistently over the k-nearest-neighbour graph (Hoppe
  /// et al. 1992), starting outwards from the highest point.
  bool orient = true;
};
/// Estimates unit normals (PCL NormalEstimationOMP; deterministic). Points without enough neighbours
/// get the normal of their nearest neighbour that has one.
void estimate_normals(PointCloud& cloud, const NormalOptions& options);

struct MlsOptions {
  Length radius = Length::spacings(4.0);
  int polynomial_order = 2;
};
/// Moving-least-squares projection of the points (PCL MovingLeastSquares), keeping their order.
void smooth_mls(PointCloud& cloud, const MlsOptions& options, const CloudScale& scale);

}  // namespace scanmesh
