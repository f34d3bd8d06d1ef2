// Large noisy meshes for the scaling measurements (issue: a million faces in seconds): the 202k-face dragon
// split 1 -> 4 (every edge at its midpoint) `levels` times, then Gaussian noise of 0.3 mean edges in random
// directions (seed 1), written as binary PLY. The surface stays the dragon's; only the sampling gets finer.
// usage: scanmesh_big_meshes [DATA_DIR] [OUT_DIR] [--levels N]   (default ../shared/data, /tmp, N = 2)
//   writes OUT_DIR/dragon-L<k>.ply for k = 0..N (202k, 809k, 3.2M faces, ...)
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <unordered_map>

#include "scanmesh/add_noise.h"
#include "scanmesh/mesh_io.h"
#include "guarded_main.h"

using namespace scanmesh;
namespace fs = std::filesystem;

namespace {

Mesh split_edges(const Mesh& m) {
  Mesh out;
  out.positions = m.positions;
  out.faces.reserve(4 * m.faces.size());
  std::unordered_map<std::uint64_t, int> mid;
  mid.reserve(3 * m.faces.size());
  auto midpoint = [&](int a, int b) {
    const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
    const auto [it, fresh] = mid.try_emplace(key, static_cast<int>(out.positions.size()));
    if (fresh) out.positions.push_back(0.5 * (m.positions[a] + m.positions[b]));
    return it->second;
  };
  for (const Face& f : m.faces) {
    const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
    out.faces.push_back({f[0], ab, ca});
    out.faces.push_back({ab, f[1], bc});
    out.faces.push_back({ca, bc, f[2]});
    out.faces.push_back({ab, bc, ca});
  }
  return out;
}

}  // namespace

static int run(int argc, char** argv) {
  fs::path data = "../shared/data", out = fs::temp_directory_path();
  int levels = 2, positional = 0;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--levels") && i + 1 < argc) levels = std::atoi(argv[++i]);
    else if (positional++ == 0) data = argv[i];
    else out = argv[i];
  }
  const fs::path dragon = data / "meshes" / "dragon-202k.ply";
  if (!fs::exists(dragon)) {
    std::printf("skipped: %s not found\n", dragon.c_str());
    return 0;
  }
  Mesh m = read_mesh(dragon.string());
  for (int k = 0; k <= levels; ++k) {
    if (k > 0) m = split_edges(m);
    Mesh noisy = m;
    NoiseOptions no;
    no.level = 0.3;
    add_noise(noisy, no);
    const fs::path file = out / ("dragon-L" + std::to_string(k) + ".ply");
    write_mesh(noisy, file.string());
    std::printf("%s: %zu vertices, %zu faces\n", file.c_str(), noisy.positions.size(), noisy.faces.size());
  }
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
