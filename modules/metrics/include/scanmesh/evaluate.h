#pragma once
// Quality metrics of a mesh, alone and against a reference (Yadav et al. 2019, sec. 6; Metro-style distances).
#include <optional>
#include <string>
#include <vector>

#include "scanmesh/json.h"
#include "scanmesh/mesh.h"

namespace scanmesh {

/// Topology counts of one mesh.
struct TopologyStats {
  std::size_t vertices = 0, faces = 0, edges = 0;
  std::size_t boundary_edges = 0, boundary_loops = 0, nonmanifold_edges = 0;
  std::size_t components = 0, isolated_vertices = 0, degenerate_faces = 0;
  std::size_t inconsistent_edges = 0;  ///< two-face edges whose faces run along them in the same direction
  std::size_t nonfinite_vertices = 0;  ///< vertices with a NaN or infinite coordinate
};

/// Everything `evaluate` measures. Per-element arrays are kept for histograms and coloured renderings.
struct MeshMetrics {
  TopologyStats topology;
  double bbox_diagonal = 0.0;
  double mean_edge_length = 0.0;

  // Triangle quality Q = circumradius / shortest edge (1/sqrt(3) ~ 0.577 is equilateral; lower is better).
  std::vector<double> face_quality;  ///< per face; +inf for degenerate faces
  double quality_mean = 0.0;         ///< over non-degenerate faces
  double quality_max = 0.0;

  // Edges with exactly two faces and the angle between those faces' normals (0 = flat), for histograms
  // and for drawing feature edges.
  std::vector<std::array<int, 2>> manifold_edges;
  std::vector<double> dihedral_deg;

  // Against the reference (present only when one is given).
  bool has_reference = false;
  bool same_connectivity = false;          ///< same face list: MSAE and flips are defined
  std::vector<double> face_angle_error;    ///< degrees, per face (same_connectivity only)
  double msae_deg = 0.0;                   ///< mean face-normal angle error
  std::size_t flipped_faces = 0;           ///< faces more than 90 degrees from the reference normal
  std::vector<double> vertex_distance;     ///< exact distance of each vertex to the reference surface
  double ev = 0.0;                         ///< sqrt(sum A_i d_i^2 / sum A_i), A_i = area around vertex i
  double ev_relative = 0.0;                ///< ev / reference bbox diagonal
  double distance_mean = 0.0, distance_rms = 0.0;
  double hausdorff_to_reference = 0.0;     ///< max over this mesh's vertices of the distance to the reference
  double hausdorff_from_reference = 0.0;   ///< max over the reference's vertices of the distance to this mesh
  double hausdorff = 0.0;                  ///< max of both
  std::optional<double> volume_change;     ///< (V - V_ref) / V_ref when both are closed and V_ref != 0
};

/// Topology counts (boundary loops, non-manifold edges, components, ...).
TopologyStats topology_stats(const Mesh& mesh);

/// Signed volume enclosed by a closed, consistently oriented mesh (divergence theorem).
double signed_volume(const Mesh& mesh);

/// Measures `mesh`, and against `reference` if given. Parallel; independent of the thread count.
MeshMetrics evaluate(const Mesh& mesh, const Mesh* reference);

/// Mean angle (degrees) between each face's normal and the normal of the nearest reference face (the one
/// holding the closest point to the face's centroid), unsigned: a reversed face counts as aligned. For
/// meshes whose faces do not correspond to the reference's (e.g. reconstructed from a scan).
double nearest_face_normal_error(const Mesh& mesh, const Mesh& reference);

/// Share of the reference surface that the mesh covers where a scan saw it: among reference face centroids
/// within `radius` of a scan point, the fraction within `radius` of the mesh.
double scanned_coverage(const Mesh& mesh, const Mesh& reference, const std::vector<Vec3>& scan, double radius);

struct ScanFit;

/// The summary numbers (no per-element arrays) as a JSON object; with a scan fit (scan_fit.h) it becomes
/// the object's "scan_fit" member.
void write_json(JsonWriter& writer, const MeshMetrics& metrics, const ScanFit* fit = nullptr);
/// The same as a whole JSON document (what `scanmesh eval --json` writes).
std::string metrics_json(const MeshMetrics& metrics, const ScanFit* fit = nullptr);

}  // namespace scanmesh
