#pragma once
// Peers for the corpus benches, written here from their textbook definitions (not anyone's code), so
// --auto can be compared with the methods the issues name as the best peers on organic meshes.
#include "scanmesh/mesh.h"

namespace scanmesh::bench {

/// Iterations the benches give the peer: the measured peers ran OpenMesh's bi-Laplacian smoother
/// for 10.
inline constexpr int kBilaplacianIterations = 10;

/// Bi-Laplacian (C1) smoothing with uniform weights, Jacobi style: each iteration moves every interior
/// vertex by -(L^2 p)_i / (L^2)_ii, with L = I - (mean of the neighbours) (the umbrella operator);
/// boundary vertices stay. All vertices move together per iteration (Jacobi), so the result does not
/// depend on the vertex order.
void bilaplacian_smooth(Mesh& mesh, int iterations);

}  // namespace scanmesh::bench
