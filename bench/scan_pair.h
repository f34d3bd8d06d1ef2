#pragma once
// A denoising pair made the way scans are (bench/scan_pairs.cpp, and the tests of --auto on scanned
// triangulations): a model ray-cast twice with the same rays, without and with depth noise; greedy
// projection of the noise-free points, cleaned up as the main job does, is the clean mesh, and the same
// faces over the noisy points the noisy one. With `flips`, the noisy mesh's edges are then flipped towards
// Delaunay as the main job does (judged on the noisy points, as there) and the clean mesh takes its faces.
#include <functional>
#include <unordered_map>

#include "scanmesh/clean_cloud.h"
#include "scanmesh/clean_mesh.h"
#include "scanmesh/combine_views.h"
#include "scanmesh/flip_edges.h"
#include "scanmesh/triangulate.h"
#include "scanmesh/virtual_scan.h"

namespace scanmesh::bench {

/// Fills `clean` and `noisy` (same vertices and faces) from `model` scanned with `options`; false if the
/// two scans do not line up (or hold fewer than 100 points).
inline bool make_scan_pair(const Mesh& model, const VirtualScanOptions& options, Mesh& clean, Mesh& noisy,
                           bool flips = false) {
  VirtualScanOptions exact = options;
  exact.noise = 0.0;
  const PointCloud c0 = merge_views(virtual_scan(model, exact));
  const PointCloud c1 = merge_views(virtual_scan(model, options));
  if (c0.size() != c1.size() || c0.size() < 100) return false;
  PointCloud with_normals = c0;
  estimate_normals(with_normals, NormalOptions{});
  clean = triangulate_gp3(with_normals, Gp3Options{}, measure_scale(with_normals));  // vertices: the points in order
  // Clean-up may drop, reorder or split vertices; positions stay exact, so each is found again by position.
  struct Key {
    std::size_t operator()(const Vec3& p) const {
      const std::hash<double> h;
      return h(p.x()) ^ (h(p.y()) * 31) ^ (h(p.z()) * 131);
    }
  };
  std::unordered_map<Vec3, int, Key> index;
  for (std::size_t i = 0; i < c0.size(); ++i) index.emplace(c0.points[i], static_cast<int>(i));
  clean_mesh(clean, CleanupOptions{});
  noisy = clean;
  for (std::size_t v = 0; v < clean.positions.size(); ++v) {
    const auto it = index.find(clean.positions[v]);
    if (it == index.end()) return false;
    noisy.positions[v] = c1.points[static_cast<std::size_t>(it->second)];
  }
  if (flips) {
    flip_edges(noisy);
    clean.faces = noisy.faces;
  }
  clean.vertex_properties.clear();  // (the noise-free normals would not be the noisy mesh's)
  noisy.vertex_properties.clear();
  return !clean.faces.empty();
}

}  // namespace scanmesh::bench
