#pragma once
// Per-face and per-vertex geometric quantities shared by the denoiser, the metrics and the noise module.
#include <vector>

#include "scanmesh/mesh.h"
#include "scanmesh/topology.h"

namespace scanmesh {

/// Unit normals, areas and centroids of all faces. A degenerate face (area below 1e-300 or collinear
/// corners) gets a zero normal and zero area, so it carries no weight anywhere; nothing becomes NaN.
struct FaceGeometry {
  std::vector<Vec3> normals;
  std::vector<double> areas;
  std::vector<Vec3> centroids;
};

/// Centroid (a + b + c) / 3 of triangle `f`: the one expression compute_face_geometry stores and the
/// denoiser's iterations recompute, so both give the same bits.
inline Vec3 face_centroid(const std::vector<Vec3>& positions, const Face& f) {
  return (positions[f[0]] + positions[f[1]] + positions[f[2]]) / 3.0;
}

/// Computes FaceGeometry for `positions` (which may differ from mesh.positions, e.g. while iterating).
/// Without `with_centroids` the centroids are left empty (and their memory freed): the denoiser's
/// iterations compute them where they are needed, (a + b + c) / 3 with the same bits.
/// Runs in parallel; the result does not depend on the thread count.
void compute_face_geometry(const std::vector<Vec3>& positions, const std::vector<Face>& faces,
                           FaceGeometry& out, bool with_centroids = true);

/// Unit normal and area of one triangle (zero normal if degenerate).
Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c, double* area = nullptr);

/// Triangle shape Q = circumradius / shortest edge (1/sqrt(3) for an equilateral triangle, larger is worse;
/// +infinity for a degenerate triangle).
double triangle_shape(const Vec3& a, const Vec3& b, const Vec3& c);

/// Mean length over the mesh's unique edges (0 for a mesh without edges).
double mean_edge_length(const Mesh& mesh, const Topology& topology);

/// Area-weighted vertex normals from the given face normals (zero for isolated vertices).
std::vector<Vec3> vertex_normals(const Topology& topology, const FaceGeometry& geometry);
/// The same for one vertex (the same bits as vertex_normals()[v]), without a table for all of them.
Vec3 vertex_normal(const Topology& topology, const FaceGeometry& geometry, std::size_t v);

/// Axis-aligned bounding-box diagonal length of the positions (0 if fewer than two points).
double bbox_diagonal(const std::vector<Vec3>& positions);

/// The faces whose triangle is not an exact copy of an earlier face's (the same three corner positions
/// in any order, whether or not they share vertices), ascending. Searches that only need the surface
/// (closest points, ray hits) skip the copies, which a spatial index cannot separate.
std::vector<int> distinct_triangles(const Mesh& mesh);

}  // namespace scanmesh
