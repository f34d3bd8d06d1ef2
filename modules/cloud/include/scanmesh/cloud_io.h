#pragma once
// Reading point clouds: PCD (ascii, binary, binary_compressed; organized or not; RGB and normals, via
// PCL), PLY point clouds (ascii/binary, normals, colours), Stanford range-grid PLY (the `range_grid`
// element, organized; its pose comes from a `.conf` file beside it), and XYZ text (3 or 6 columns:
// position, or position and normal).
#include <string>
#include <vector>

#include "scanmesh/point_cloud.h"

namespace scanmesh {

/// Reads a cloud, chosen by extension (.pcd .ply .xyz .txt .pts). NaN points are dropped from
/// unorganized clouds and kept as holes in organized ones. A Stanford range scan is transformed by its
/// pose from a `.conf` file in the same folder (any *.conf naming it in a `bmesh` line), with the sensor
/// origin set to the scan's camera position. A PCD VIEWPOINT at the origin counts as the sensor position
/// only for organized clouds (for unorganized ones it is usually just the default). Throws InputError naming the file and the problem (missing,
/// empty, wrong header, truncated binary, no finite point).
PointCloud read_cloud(const std::string& path, std::vector<std::string>* warnings = nullptr);

/// True if read_cloud understands this (lower-case, dotted) extension.
bool is_cloud_extension(const std::string& extension);

/// Writes a cloud as binary PLY (positions, normals and colours when present), atomically.
void write_cloud_ply(const PointCloud& cloud, const std::string& path);

/// Writes a cloud as binary-compressed PCD, keeping its organisation (width x height, NaN holes) and its
/// sensor pose in VIEWPOINT, atomically.
void write_cloud_pcd(const PointCloud& cloud, const std::string& path);

}  // namespace scanmesh
