#pragma once
// scanmesh's own point-cloud type: plain vectors, no PCL types, so code that uses clouds compiles fast.
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "scanmesh/mesh.h"

namespace scanmesh {

/// A point cloud, unorganized (height == 1) or organized as a width x height image (row-major, with
/// NaN points as holes). Normals and colours are optional (empty when absent).
struct PointCloud {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;                       ///< empty or one per point
  /// Whether `normals` tell which side is outside (used to orient re-estimated normals). False for PCD
  /// normals without a real VIEWPOINT: PCL turns them towards the default viewpoint at the origin.
  bool normals_oriented = true;
  std::vector<std::array<std::uint8_t, 3>> colours;  ///< empty or one per point (r, g, b)
  int width = 0;   ///< points per row (== size for unorganized clouds)
  int height = 1;  ///< rows (1 for unorganized clouds)
  /// Sensor position and orientation (rotation applied to sensor-frame directions), when known.
  std::optional<Vec3> sensor_origin;
  Eigen::Matrix3d sensor_orientation = Eigen::Matrix3d::Identity();

  [[nodiscard]] std::size_t size() const { return points.size(); }
  [[nodiscard]] bool organized() const { return height > 1; }
  [[nodiscard]] bool has_normals() const { return !normals.empty(); }
  [[nodiscard]] bool has_colours() const { return !colours.empty(); }
  /// Number of points with finite coordinates.
  [[nodiscard]] std::size_t finite_count() const;
};

/// Scale of a cloud: mean nearest-neighbour spacing and bounding-box diagonal of its finite points
/// (measure_scale in neighbourhoods.h); what lengths like "3*spacing" resolve against.
struct CloudScale {
  double spacing = 0.0;
  double diagonal = 0.0;
};

/// Removes NaN/infinite points (and their normals/colours); the result is unorganized.
void drop_non_finite(PointCloud& cloud);

/// Finite points at exactly the same position (a view saved twice, an exporter's filler, a depth camera's
/// "no return" written as 0 0 0): an unorganized cloud keeps the first of them and loses the others; in an
/// organized one all of them become NaN holes (the grid stays; two pixels' rays meet only at the sensor,
/// so a shared position is a marker, not a measurement). Returns how many points went. k-d trees cannot
/// split a position that many points share, so every later neighbour search around it would be quadratic.
std::size_t merge_copies(PointCloud& cloud);

/// For each point, the index of the first point at exactly its position (its own index if it is the
/// first; -0 and +0 are one position; non-finite points are never copies), or an empty vector if no
/// position is shared by `crowd` points or more (by default: if no two finite points share one). Linear
/// time (hashed); throws std::length_error beyond 2^32 points. A k-d tree cannot split a position many
/// points share: searches near it scan them all, so searches over crowded points go by position.
std::vector<std::uint32_t> first_copies(const std::vector<Vec3>& points, std::size_t crowd = 2);

/// Points grouped by position (`first` from first_copies, non-empty): group g holds the points
/// members[start[g], start[g + 1]), ascending, its first point first; groups in the order of their first
/// points; group_of[i] is point i's group.
struct CopyGroups {
  std::vector<int> group_of, start, members;
  [[nodiscard]] std::size_t size() const { return start.size() - 1; }
  [[nodiscard]] int count(std::size_t g) const { return start[g + 1] - start[g]; }
  [[nodiscard]] int first_of(std::size_t g) const { return members[static_cast<std::size_t>(start[g])]; }
};
CopyGroups group_copies(const std::vector<std::uint32_t>& first);

/// Keeps the points whose flag is set (attributes follow); the result is unorganized.
void keep_points(PointCloud& cloud, const std::vector<std::uint8_t>& keep);

/// Why the finite points cannot outline a surface (all at one position, all on one line, or spread over
/// less than single precision can measure), or "" if
/// they can. Stages that fit planes to neighbours check this first: PCL's neighbour searches also turn
/// quadratic on a cloud of one repeated point.
std::string surface_problem(const PointCloud& cloud);

/// The box around the finite points; empty (lo > hi) if there are none.
struct Box {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
  [[nodiscard]] bool empty() const { return !(lo.x() <= hi.x()); }
};
Box finite_box(const std::vector<Vec3>& points);

/// The centre of the finite points' bounding box (zero if there are none). PCL holds points in single
/// precision, whose step at georeferenced coordinates (UTM: 5e5 m east, 4e6 m north) is 0.03-0.5 m:
/// points go to it relative to this origin, subtracted in double precision, and come back with it added.
Vec3 local_origin(const std::vector<Vec3>& points);

/// Moves a cloud rigidly: points, normals and the sensor pose (NaN holes stay holes).
void transform_cloud(PointCloud& cloud, const Eigen::Isometry3d& pose);

}  // namespace scanmesh
