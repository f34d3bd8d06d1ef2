#pragma once
// Mesh clean-up after meshing: the options struct is the schema of the mesh.cleanup pipeline stage.
#include <optional>
#include <string>

#include "scanmesh/mesh.h"
#include "scanmesh/schema.h"

namespace scanmesh {

struct CleanupOptions {
  bool remove_degenerate = true;
  bool remove_duplicates = true;
  bool fix_nonmanifold = true;
  int min_component_faces = 10;
  bool orient = true;
  static const Schema<CleanupOptions>& schema() {
    static const Schema<CleanupOptions> s =
        Schema<CleanupOptions>()
            .flag("remove_degenerate", &CleanupOptions::remove_degenerate, "Remove faces with a repeated vertex or zero area.")
            .flag("remove_duplicates", &CleanupOptions::remove_duplicates, "Remove faces over the same three vertices.")
            .flag("fix_nonmanifold", &CleanupOptions::fix_nonmanifold,
                  "Keep two faces per edge and split vertices that join separate fans.")
            .integer("min_component", &CleanupOptions::min_component_faces, closed(0, 1e9), "faces",
                     "Remove connected pieces with fewer faces; 0 keeps all.")
            .flag("orient", &CleanupOptions::orient, "Orient consistently: closed pieces outwards, open ones towards the sensor.");
    return s;
  }
};

/// What clean_mesh changed.
struct CleanupReport {
  std::size_t degenerate_faces = 0, duplicate_faces = 0, nonmanifold_faces = 0, split_vertices = 0;
  std::size_t small_component_faces = 0, unreferenced_vertices = 0, flipped_faces = 0;
  std::size_t fold_faces = 0;          ///< faces removed because they folded over their neighbours (unorientable)
  std::size_t unorientable_edges = 0;  ///< edges still inconsistent afterwards
};

/// Cleans the mesh in place; unreferenced vertices are dropped (vertex properties follow). Deterministic.
CleanupReport clean_mesh(Mesh& mesh, const CleanupOptions& options, const std::optional<Vec3>& sensor = std::nullopt);

}  // namespace scanmesh
