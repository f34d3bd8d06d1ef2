#pragma once
// Mesh connectivity the algorithms need, built once in compressed (CSR) arrays so loops over a vertex's
// or a face's neighbours read contiguous memory.
#include <cstdint>
#include <vector>

#include "scanmesh/mesh.h"

namespace scanmesh {

/// A list of index lists stored back to back: row i is indices[offsets[i] .. offsets[i+1]).
struct Adjacency {
  std::vector<int> offsets{0};
  std::vector<int> indices;

  [[nodiscard]] std::size_t rows() const { return offsets.size() - 1; }
  [[nodiscard]] int size(std::size_t i) const { return offsets[i + 1] - offsets[i]; }
  [[nodiscard]] const int* begin(std::size_t i) const { return indices.data() + offsets[i]; }
  [[nodiscard]] const int* end(std::size_t i) const { return indices.data() + offsets[i + 1]; }
};

/// Connectivity of a triangle mesh. Works on any index soup: degenerate faces, isolated vertices,
/// non-manifold edges and several components are all represented (nothing is dropped).
struct Topology {
  Adjacency vertex_faces;     ///< faces around each vertex, ascending
  Adjacency vertex_vertices;  ///< vertices sharing an edge with each vertex, ascending
  std::vector<std::array<int, 2>> edges;  ///< unique undirected edges, (smaller, larger) index, sorted
  Adjacency edge_faces;                   ///< faces on each edge, ascending (1 = boundary, >2 = non-manifold)
  std::vector<std::array<int, 3>> face_edges;  ///< edge index of (f[0],f[1]), (f[1],f[2]), (f[2],f[0])
  /// Faces sharing an edge with each face, ascending, no duplicates. On a non-manifold edge only the
  /// faces next to each other in edge_faces are linked (linear size on fans of thousands of faces).
  Adjacency face_faces;
  std::vector<std::uint8_t> boundary_vertex;  ///< 1 if the vertex lies on a boundary edge
  /// Closed boundary loops as vertex sequences, following the faces' orientation. Only vertices with
  /// exactly two boundary edges are chained; open chains (at non-manifold vertices) are listed too.
  std::vector<std::vector<int>> boundary_loops;
  std::vector<std::uint8_t> boundary_loop_closed;  ///< 1 if the loop's last vertex connects to its first

  [[nodiscard]] bool is_boundary_edge(std::size_t e) const { return edge_faces.size(e) == 1; }
  [[nodiscard]] bool is_nonmanifold_edge(std::size_t e) const { return edge_faces.size(e) > 2; }
  [[nodiscard]] std::size_t num_boundary_edges() const;
  [[nodiscard]] std::size_t num_nonmanifold_edges() const;
};

/// Builds all of the above in O(F log F). Face indices must be valid (see validate_mesh). Without
/// `with_face_faces`, face_faces is left empty (the denoiser's ball neighbourhoods do not need it).
Topology build_topology(const Mesh& mesh, bool with_face_faces = true);

/// (Re)builds `t.vertex_vertices` from its edges, as build_topology does: for a caller that freed the table
/// while it held other memory and needs it again later.
void add_vertex_vertices(Topology& t);

/// (Re)builds `t.face_faces` of a mesh of `num_faces` faces from its edges' faces, as build_topology does
/// with `with_face_faces` (face_edges is not read: a caller may have freed it).
void add_face_faces(Topology& t, std::size_t num_faces);

/// Number of connected components (through shared vertices) among vertices used by faces.
std::size_t count_components(const Mesh& mesh, const Topology& topology);

/// Per vertex, the smallest vertex index of its piece (pieces joined through the vertices faces share;
/// a vertex no face uses is a piece of its own). No topology needed: one union-find pass over the faces.
std::vector<int> vertex_pieces(const Mesh& mesh);

}  // namespace scanmesh
