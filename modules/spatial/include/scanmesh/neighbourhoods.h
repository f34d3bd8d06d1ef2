#pragma once
// Fixed-radius neighbourhoods of 3D points through a FLANN k-d tree.
#include <vector>

#include "scanmesh/mesh.h"
#include "scanmesh/packed_rows.h"
#include "scanmesh/point_cloud.h"
#include "scanmesh/topology.h"

namespace scanmesh {

/// For every point, the indices of all points within `radius` (itself included), ascending.
/// Exact (single k-d tree, unlimited checks); parallel over queries; independent of the thread count.
/// With `max_neighbours` > 0, a row keeps only the nearest max_neighbours points (so pathological input,
/// thousands of faces on one spot, stays linear in size); `capped` then counts the rows that were cut.
/// With `spatially_ordered` (points close in space are close in the array, like the denoiser's faces) the
/// k-d tree reads `points` in place instead of keeping a reordered copy (24 bytes per point less), and
/// runs of close points share one tree query (about 40% less time on the denoiser's faces). The rows are
/// the same either way, except which of several equally distant points fill a capped row.
Adjacency radius_neighbourhoods(const std::vector<Vec3>& points, double radius, int max_neighbours = 0,
                                std::size_t* capped = nullptr, bool spatially_ordered = false);

/// The same rows as radius_neighbourhoods, packed (each row anchored at its own index): half the memory
/// when `points` are in a spatial order.
PackedRows packed_radius_neighbourhoods(const std::vector<Vec3>& points, double radius, int max_neighbours = 0,
                                        std::size_t* capped = nullptr, bool spatially_ordered = false);

/// For every point, its k nearest other points, nearest first (fewer if the cloud is smaller).
/// Exact; parallel; independent of the thread count.
Adjacency knn_neighbourhoods(const std::vector<Vec3>& points, int k);

/// Distance from each query to the nearest of `points` (infinity if `points` is empty).
std::vector<double> nearest_point_distances(const std::vector<Vec3>& points, const std::vector<Vec3>& queries);

/// Mean distance from each point to its nearest point at another position (copies of a point are skipped,
/// up to 127 of them; 0 for fewer than two distinct points); over more than
/// a million points, the mean over every k-th point that brings the sample within a million.
double mean_nearest_neighbour_distance(const std::vector<Vec3>& points);

/// Spacing (mean nearest-neighbour distance) and bounding-box diagonal of a cloud's finite points.
CloudScale measure_scale(const PointCloud& cloud);

}  // namespace scanmesh
