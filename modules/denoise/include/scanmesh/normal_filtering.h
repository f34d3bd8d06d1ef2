#pragma once
// Stage 1 of the robust two-stage denoiser: bilateral filtering of face normals with a robust
// similarity weight (Yadav et al. 2019, eq. 1-2).
#include <vector>

#include "scanmesh/denoise.h"
#include "scanmesh/geometry.h"
#include "scanmesh/topology.h"

namespace scanmesh {

/// Robust similarity weight g(x, sigma_s) for x = |n_i - n_j|.
double robust_weight(RobustEstimator estimator, double x, double sigma_s);

/// n~_i = normalize( sum_{j in Omega_i} a_j f(|c_i - c_j|, sigma_c) g(|n_i - n_j|, sigma_s) n_j ),
/// with f(d) = exp(-d^2 / (2 sigma_c^2)). `neighbourhoods` row i is Omega_i. A face whose weights all
/// vanish keeps its own normal. Writes `filtered` (resized to the face count).
void filter_face_normals(const FaceGeometry& geometry, const Adjacency& neighbourhoods, double sigma_c,
                         double sigma_s, RobustEstimator estimator, std::vector<Vec3>& filtered);

/// The mean distance c_a between centroids of edge-adjacent faces (mean edge length if no face has a
/// neighbour; 0 for an empty mesh).
double mean_centroid_distance(const Mesh& mesh, const Topology& topology, const FaceGeometry& geometry);

/// Omega_i for every face: centroids within `radius`, optionally only through edge-adjacent faces.
Adjacency face_neighbourhoods(const Topology& topology, const FaceGeometry& geometry, double radius,
                              NeighbourhoodKind kind);

}  // namespace scanmesh
