#pragma once
// Closing holes: a boundary loop is triangulated with the least folding (largest dihedral angle first,
// then area) by dynamic programming over its vertices, and the patch is refined until its edges are as
// long as the loop's, its new vertices relaxed to a smooth membrane. The surface around is not touched.
#include <cstddef>
#include <vector>

#include "scanmesh/mesh.h"

namespace scanmesh {

/// What one loop became.
struct FilledHole {
  bool filled = false;             ///< false: too many vertices, or beyond the work budget (see `fill_holes`)
  std::size_t first_face = 0;      ///< the patch's faces are mesh.faces[first_face, first_face + faces)
  std::size_t faces = 0;
  std::size_t first_vertex = 0;    ///< its new vertices are positions[first_vertex, first_vertex + vertices)
  std::size_t vertices = 0;
};

/// Loops longer than this are left open: the triangulation costs loop length cubed.
constexpr std::size_t kMaxFillLoopVertices = 400;

/// Fills every loop of `loops`: each a ring of vertex indices in the order closed_boundary_loops walks them
/// (against the orientation of the faces on its edges, so the patch continues that orientation). A patch
/// never adds an edge the mesh or an earlier patch already has (a loop whose vertices are joined
/// elsewhere gets a triangulation around that or, where every one would need such an edge, a fan around a
/// new vertex at the loop's centroid); a loop that passes a vertex twice is closed as its simple parts. New vertices are appended, their extra vertex
/// properties interpolated; existing vertices and faces are not changed. The triangulation costs a loop's
/// length cubed, so loops are taken shortest first within a work budget that grows with the mesh (a mesh
/// of many long loops stays near-linear); the rest stay open. Deterministic, whatever the thread count.
std::vector<FilledHole> fill_holes(Mesh& mesh, const std::vector<std::vector<int>>& loops);

/// Zips the slits of loops before they are filled: where a loop runs out to a vertex a and back
/// (..., v, a, w, ...) with v and w at the same position (copies of one vertex, which clean-up splits
/// where a removed face left two fans touching), w is welded into v and the two edges beside a become one
/// edge between two faces. A weld that would give an edge more than two faces, or a face a repeated
/// vertex, is not made. Faces referring to w then refer to v; w is left unreferenced (clean-up drops it).
/// Returns what remains of the loops, each still in boundary order, without the loops zipped shut;
/// `zipped` (if given) gets how many were.
std::vector<std::vector<int>> zip_slits(Mesh& mesh, const std::vector<std::vector<int>>& loops, std::size_t* zipped = nullptr);

/// Removes the faces of the patches for which `keep` is false and the vertices they added; the other
/// vertices and faces keep their order, and the kept patches' ranges are updated (removed ones become
/// not `filled`).
void remove_patches(Mesh& mesh, std::vector<FilledHole>& patches, const std::vector<char>& keep);

}  // namespace scanmesh
