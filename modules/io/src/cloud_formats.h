#pragma once
// Readers and writers behind read_cloud / write_cloud_pcd, on bytes in memory (so the fuzz harnesses can
// drive them without files). Each checks every count in a header against the bytes that follow before
// allocating, and throws InputError naming `file` and the problem.
#include <string>
#include <string_view>
#include <vector>

#include "scanmesh/point_cloud.h"

namespace scanmesh::detail {

/// PCD v0.7: ascii, binary, binary_compressed; fields x y z, normal_x/y/z, rgb/rgba (others ignored).
PointCloud decode_pcd(std::string_view data, const std::string& file);
/// binary_compressed PCD with float x y z (+ normals, + rgb), organisation and VIEWPOINT kept.
std::string encode_pcd(const PointCloud& cloud);

/// Text clouds; `columns` ("x,y,z,i,r,g,b") overrides what the header or the data suggest.
PointCloud decode_xyz(std::string_view data, const std::string& file, const std::string& columns,
                      std::vector<std::string>& warnings);

}  // namespace scanmesh::detail
