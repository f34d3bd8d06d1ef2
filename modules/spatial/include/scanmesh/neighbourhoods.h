#pragma once
// Fixed-radius neighbourhoods of 3D points through a FLANN k-d tree.
#include <vector>

#include "scanmesh/mesh.h"
#include "scanmesh/topology.h"

namespace scanmesh {

/// For every point, the indices of all points within `radius` (itself included), ascending.
/// Exact (single k-d tree, unlimited checks); parallel over queries; independent of the thread count.
Adjacency radius_neighbourhoods(const std::vector<Vec3>& points, double radius);

/// Mean distance from each point to its nearest other point (0 for fewer than two points).
double mean_nearest_neighbour_distance(const std::vector<Vec3>& points);

}  // namespace scanmesh
