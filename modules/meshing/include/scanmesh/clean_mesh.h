#pragma once
// Mesh clean-up after meshing: the options struct is the schema of the mesh.cleanup pipeline stage.
#include <optional>
#include <string>

#include "scanmesh/mesh.h"

namespace scanmesh {

struct CleanupOptions {
  bool remove_degenerate = true;  ///< faces with a repeated vertex or (numerically) zero area
  bool remove_duplicates = true;  ///< faces over the same three vertices (either orientation)
  bool fix_nonmanifold = true;    ///< edges with > 2 faces keep two; vertices joining separate fans are split
  int min_component_faces = 10;   ///< connected pieces with fewer faces are removed (0 = keep all)
  bool orient = true;             ///< consistent orientation; closed pieces outwards, open ones towards the sensor
};

/// What clean_mesh changed.
struct CleanupReport {
  std::size_t degenerate_faces = 0, duplicate_faces = 0, nonmanifold_faces = 0, split_vertices = 0;
  std::size_t small_component_faces = 0, unreferenced_vertices = 0, flipped_faces = 0;
  std::size_t unorientable_edges = 0;  ///< edges still inconsistent afterwards (non-orientable pieces)
};

/// Cleans the mesh in place; unreferenced vertices are dropped (vertex properties follow). Deterministic.
CleanupReport clean_mesh(Mesh& mesh, const CleanupOptions& options, const std::optional<Vec3>& sensor = std::nullopt);

}  // namespace scanmesh
