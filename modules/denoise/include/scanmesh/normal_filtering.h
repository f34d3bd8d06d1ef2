#pragma once
// Stage 1 of the robust two-stage denoiser: bilateral filtering of face normals with a robust
// similarity weight (Yadav et al. 2019, eq. 1-2).
#include <cstdint>
#include <vector>

#include "scanmesh/denoise.h"
#include "scanmesh/geometry.h"
#include "scanmesh/packed_rows.h"
#include "scanmesh/topology.h"

namespace scanmesh {

/// Robust similarity weight g(x, sigma_s) for x = |n_i - n_j|.
double robust_weight(RobustEstimator estimator, double x, double sigma_s);

/// What the Tukey kernel rebuilds on every call: each face's normal, area and centroid in single
/// precision (32 bytes a face). A caller that filters repeatedly passes the same one so nothing is
/// allocated after the first call.
struct FilterWork {
  struct alignas(32) Record {
    float nx, ny, nz, area, cx, cy, cz, unused;
  };
  std::vector<Record> records;
  /// Where the centroids come from when the geometry has none (compute_face_geometry without them).
  const std::vector<Vec3>* positions = nullptr;
  const std::vector<Face>* faces = nullptr;
  /// True: `records` already hold the geometry's faces (refreshed with it in one pass, as the denoiser's
  /// iterations do) and the next call uses them as they are; the call clears it.
  bool records_ready = false;
  /// `records` sized for n faces (allocated once, with huge pages asked for: the kernel reads them at random).
  void size_records(std::size_t n);
  /// Face f's record: its normal and area, and its centroid less `origin` (face 0's centroid).
  static Record record(const Vec3& normal, double area, const Vec3& centroid, const Vec3& origin) {
    const Vec3 c = centroid - origin;
    return {static_cast<float>(normal.x()), static_cast<float>(normal.y()), static_cast<float>(normal.z()), static_cast<float>(area),
            static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z()), 0.0f};
  }
};

/// The denoiser's face pass, from one read of each face's corners: the face geometry (normals and areas;
/// no centroids), `work`'s records for the next filtering (which then skips its own packing) and, with
/// sliver_limit > 0, the sliver guard's flags (returns how many). The same bits as compute_face_geometry,
/// the kernel's packing and mark_new_slivers(positions, input, ...), which read the corners once each
/// (together a tenth of an iteration's time on the 810k-face dragon).
std::size_t refresh_faces(const std::vector<Vec3>& positions, const std::vector<Vec3>& input, const std::vector<Face>& faces,
                          double sliver_limit, FaceGeometry& geometry, FilterWork& work, std::vector<std::uint8_t>& slivers);

/// n~_i = normalize( sum_{j in Omega_i} a_j f(|c_i - c_j|, sigma_c) g(|n_i - n_j|, sigma_s) n_j ),
/// with f(d) = exp(-d^2 / (2 sigma_c^2)). `neighbourhoods` row i is Omega_i. A face whose weights all
/// vanish keeps its own normal. Writes `filtered` (resized to the face count).
/// With `face_sigma`, face i uses sigma_s = (*face_sigma)[i] instead. `filtered` may be `geometry.normals`
/// itself: the normals are then filtered in place (the Tukey kernel reads them only through `work`'s copy).
void filter_face_normals(const FaceGeometry& geometry, const Adjacency& neighbourhoods, double sigma_c,
                         double sigma_s, RobustEstimator estimator, std::vector<Vec3>& filtered,
                         const std::vector<double>* face_sigma = nullptr, FilterWork* work = nullptr);
/// The same with the neighbourhoods packed (row i anchored at i, as packed_face_neighbourhoods makes them):
/// the same bits, in about half the memory.
void filter_face_normals(const FaceGeometry& geometry, const PackedRows& neighbourhoods, double sigma_c,
                         double sigma_s, RobustEstimator estimator, std::vector<Vec3>& filtered,
                         const std::vector<double>* face_sigma = nullptr, FilterWork* work = nullptr);

/// Instruction set the Tukey kernel of filter_face_normals uses: `best` takes AVX2 where the processor
/// has it, `sse2` never does. Both give the same bits (the lanes are summed in one fixed order); the
/// switch exists for tests and benchmarks. Not thread-safe: set it before filtering starts.
enum class FilterIsa { best, sse2 };
void set_filter_isa(FilterIsa isa);

/// The mean distance c_a between centroids of edge-adjacent faces (mean edge length if no face has a
/// neighbour; 0 for an empty mesh).
double mean_centroid_distance(const Mesh& mesh, const Topology& topology, const FaceGeometry& geometry);

/// Largest neighbourhood a face gets at a radius of `radius_factor` c_a: max(128, 32 radius_factor^2),
/// about four times what typical meshes reach (10-30 faces at 2 c_a, 20-50 at 3 c_a) and above what the
/// most uneven of the corpus reach but for a handful of faces (99.9th percentile at 2 c_a: teapot.obj 154,
/// featuretype.stl 192; at 3 c_a at most 282). On pathological input (thousands of faces on one spot, a
/// fan of faces around one edge, a book of pages on one spine) only the nearest this many are used, so the
/// work stays linear in the face count; the run says how many faces were cut.
int max_neighbourhood_size(double radius_factor);

/// Omega_i for every face: centroids within `radius`, optionally only through edge-adjacent faces; at most
/// `max_size` faces each, the nearest (`capped` counts the faces that had more). `spatially_ordered`: the
/// faces are in a spatial order (see radius_neighbourhoods).
Adjacency face_neighbourhoods(const Topology& topology, const FaceGeometry& geometry, double radius,
                              NeighbourhoodKind kind, int max_size, std::size_t* capped = nullptr,
                              bool spatially_ordered = false);

/// face_neighbourhoods, packed (row i anchored at i); a ball is packed as it is searched, so the plain
/// table is never held.
PackedRows packed_face_neighbourhoods(const Topology& topology, const FaceGeometry& geometry, double radius,
                                      NeighbourhoodKind kind, int max_size, std::size_t* capped = nullptr,
                                      bool spatially_ordered = false);

}  // namespace scanmesh
