// Prints what --auto estimates for each pair (noise level, feature fraction, chosen parameters).
#include <cstdio>
#include <filesystem>

#include "scanmesh/estimate_parameters.h"
#include "scanmesh/mesh_io.h"

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  const fs::path dir = argc > 1 ? argv[1] : "../shared/data/pairs";
  if (!fs::is_directory(dir)) {
    std::printf("skipped: %s not found\n", dir.c_str());
    return 0;
  }
  for (const auto& e : fs::directory_iterator(dir)) {
    for (const char* which : {"clean.obj", "noisy.obj"}) {
      const scanmesh::Mesh m = scanmesh::read_mesh((e.path() / which).string());
      const auto a = scanmesh::estimate_parameters(m);
      std::printf("%-22s %-10s noise %.3f plane %.3f features %.4f -> (%.2f, %.2f, %d)\n", e.path().filename().c_str(),
                  which, a.noise_level, a.exact_plane_fraction, a.feature_fraction, a.options.sigma_s, a.options.lambda,
                  a.options.iterations);
    }
  }
}
