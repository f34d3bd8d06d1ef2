#pragma once
// Edge flips towards a Delaunay triangulation of the same points. Greedy projection connects each point
// to neighbours it finds in a growing front, which leaves long slivers and many edges whose two opposite
// angles sum to more than pi; flipping such an edge to the other diagonal of its quad gives rounder
// triangles over the very same points, so no measured point moves.
#include <cstddef>

#include "scanmesh/mesh.h"

namespace scanmesh {

struct FlipReport {
  std::size_t flips = 0;  ///< edges flipped, over all rounds
  int rounds = 0;         ///< rounds that flipped at least one edge
};

/// The flip test shared by the whole-mesh flips below and hole filling's patches: whether the edge (a, b)
/// between the triangles (a, b, c) and (b, a, d) should become the quad's other diagonal (c, d), i.e. the
/// triangles (a, d, c) and (d, b, c). Yes when the angles at c and d sum past pi, neither new triangle
/// turns against the old pair (the sum of their unit normals), no triangle is degenerate, and the new
/// pair bends no more than the old one or than the angle whose cosine is `cos_max_bend` (-1: any bend).
bool should_flip(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double cos_max_bend);

/// Flips, in rounds, every interior edge whose two opposite angles sum to more than pi (each face at most
/// once per round, edges in index order, so the result does not depend on anything but the mesh), unless
/// the flip would fold (either new face turns against the two old ones' summed normal), bend the pair
/// more than it was and more than `max_bend_deg` (the angle between the two faces' normals), leave an
/// interior vertex with fewer than three faces (a boundary vertex with none), or repeat an edge the mesh
/// has. A sharp edge whose two faces are slivers along it may be flipped across when that flattens them:
/// a scan's points are never exactly on the edge, so the triangulation was cutting it anyway.
/// Edges with other than two faces, or whose faces disagree about the orientation, are left alone.
/// Stops after `max_rounds` rounds or the first round without a flip. Positions are not touched; the
/// face count and the faces' order stay the same. The faces' sides are sorted once; each later round
/// costs a pass over them plus a search per flip.
FlipReport flip_edges(Mesh& mesh, double max_bend_deg = 30.0, int max_rounds = 20);

}  // namespace scanmesh
