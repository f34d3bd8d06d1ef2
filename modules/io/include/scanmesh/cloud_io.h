#pragma once
// Reading point clouds (scanmesh's own readers, no PCL): PCD (ascii, binary, binary_compressed; organized
// or not; RGB and normals), PLY point clouds (ascii/binary, any scalar types, normals, colours), Stanford
// range-grid PLY (the `range_grid` element, organized; its pose comes from a `.conf` file beside it), and
// text clouds (.xyz .txt .csv .pts: header line, separators and column roles sniffed or given).
#include <string>
#include <string_view>
#include <vector>

#include "scanmesh/atomic_file.h"
#include "scanmesh/point_cloud.h"

namespace scanmesh {

/// How to read a cloud file; also the options of a pipeline's reader stage.
struct CloudReadOptions {
  /// Text clouds: what each column holds, e.g. "x,y,z,i,r,g,b" (x y z nx ny nz r g b, i = intensity and
  /// _ = skip are not kept). Empty: from the header line, else sniffed from the values.
  std::string columns;
};

/// Reads a cloud, chosen by extension (.pcd .ply .xyz .txt .csv .pts). NaN points are dropped from
/// unorganized clouds and kept as holes in organized ones. A Stanford range scan is transformed by its
/// pose from a `.conf` file in the same folder (any *.conf naming it in a `bmesh` line), with the sensor
/// origin set to the scan's camera position. A PCD VIEWPOINT at the origin counts as the sensor position
/// only for organized clouds (for unorganized ones it is usually just the default). Throws InputError
/// naming the file and the problem (missing, a folder, empty, unknown format with a hint for LAS/E57,
/// wrong header, counts the data cannot hold, infinite or overflowing coordinates, no finite point).
PointCloud read_cloud(const std::string& path, std::vector<std::string>* warnings = nullptr,
                      const CloudReadOptions& options = {});

/// The same on a file's bytes in memory (`file` names it in messages, its extension picks the format);
/// range scans are left in their scan frame.
PointCloud decode_cloud(std::string_view data, const std::string& file, std::vector<std::string>* warnings = nullptr,
                        const CloudReadOptions& options = {});

/// A Stanford .conf file's pose for `scan_name` ("bmesh NAME tx ty tz qx qy qz qw"): true and the pose if
/// listed. Throws InputError naming `conf_file` if that line is malformed.
bool parse_conf_pose(std::string_view conf_text, const std::string& conf_file, const std::string& scan_name,
                     Eigen::Isometry3d& pose);

/// True if read_cloud understands this (lower-case, dotted) extension.
bool is_cloud_extension(const std::string& extension);

/// True if the file holds a point cloud rather than a mesh: by extension, and for PLY by whether its
/// header announces faces (or triangle strips). Reads at most the first 4 KiB.
bool holds_cloud(const std::string& path);

/// A cloud encoded for a file with extension `extension`: ".pcd" (binary_compressed) or ".ply" (binary).
std::string encode_cloud(const PointCloud& cloud, const std::string& extension);
/// The same bytes handed to `sink`: PLY in pieces of about a megabyte (as encode_mesh), PCD in one piece
/// (its binary_compressed block is compressed whole).
void encode_cloud(const PointCloud& cloud, const std::string& extension, const ByteSink& sink);

/// Writes a cloud as binary PLY (positions, normals and colours when present), atomically.
void write_cloud_ply(const PointCloud& cloud, const std::string& path);

/// Writes a cloud as binary-compressed PCD (positions, normals and colours when present), keeping its
/// organisation (width x height, NaN holes) and its sensor pose in VIEWPOINT, atomically.
void write_cloud_pcd(const PointCloud& cloud, const std::string& path);

}  // namespace scanmesh
