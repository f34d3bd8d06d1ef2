// libFuzzer harness for hole filling: any mesh the OFF reader accepts, cleaned the way mesh.auto cleans
// greedy projection's output, has its loops' slits zipped (copies of a vertex at one position welded, as
// mesh.auto does), every remaining loop closed and half of the patches taken out again, and the result judged
// against the loops it had before (as the final report judges a mesh against the one meshing made).
// The contract under test: no crash, no undefined behaviour, no hang (a loop's cubic cost is budgeted)
// and every face index in range afterwards.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "scanmesh/clean_mesh.h"
#include "scanmesh/errors.h"
#include "scanmesh/fill_holes.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/scan_fit.h"

namespace {

void check_indices(const scanmesh::Mesh& m) {
  for (const scanmesh::Face& f : m.faces)
    for (int v : f)
      if (v < 0 || static_cast<std::size_t>(v) >= m.num_vertices()) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    scanmesh::Mesh m = scanmesh::decode_mesh(bytes, "fuzz.off");
    if (m.num_faces() > 4000) return 0;
    scanmesh::clean_mesh(m, scanmesh::CleanupOptions{});
    if (m.faces.empty()) return 0;
    double edge = 0.0;
    for (const scanmesh::Face& f : m.faces) edge += (m.positions[f[1]] - m.positions[f[0]]).norm();
    edge /= static_cast<double>(m.num_faces());
    if (!(edge > 0.0) || !std::isfinite(edge)) return 0;
    const scanmesh::ScanFit fit = scanmesh::measure_scan_fit(m, m.positions, edge);
    std::vector<std::vector<int>> rings;
    for (const auto& loop : fit.loops) rings.push_back(loop.ring);
    rings = scanmesh::zip_slits(m, rings);
    check_indices(m);
    std::vector<scanmesh::FilledHole> patches = scanmesh::fill_holes(m, rings);
    check_indices(m);
    std::vector<char> keep(patches.size());
    for (std::size_t i = 0; i < keep.size(); ++i) keep[i] = static_cast<char>(i % 2);
    scanmesh::remove_patches(m, patches, keep);
    check_indices(m);
    if (!m.faces.empty()) {  // judged again, its loops against those of the mesh before the closing (mesh.auto's final report)
      const scanmesh::ScanFit after = scanmesh::measure_scan_fit(m, m.positions, edge, false, &fit);
      if (after.rims + after.gaps + after.holes != after.loops.size()) __builtin_trap();
    }
  } catch (const scanmesh::Error&) {
  }
  return 0;
}
