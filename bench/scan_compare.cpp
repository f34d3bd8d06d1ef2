// Scan -> mesh -> denoise on virtual scans of clean meshes with known ground truth: normal error against
// the clean mesh (unsigned, nearest face), E_v / bbox diagonal, coverage of what the scan saw, seconds.
// usage: scanmesh_scan_compare [PAIRS_DIR] [model ...] [--voxel N]   (N: voxel leaf in point spacings before
// meshing; default models fandisk-0.3 block-0.4; skips cleanly if PAIRS_DIR is absent)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "scanmesh/clean_cloud.h"
#include "scanmesh/clean_mesh.h"
#include "scanmesh/denoise.h"
#include "scanmesh/auto_denoise.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/triangulate.h"
#include "scanmesh/combine_views.h"
#include "scanmesh/virtual_scan.h"
#include "guarded_main.h"

using namespace scanmesh;

namespace {

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void report(const char* model, const char* stage, const Mesh& m, const Mesh& clean, const PointCloud& scan, double spacing,
            double seconds) {
  const MeshMetrics r = evaluate(m, &clean);
  std::printf("| %-12s | %-22s | %7zu | %6.2f | %.3e | %5.1f%% | %6.2f |\n", model, stage, m.num_faces(),
              nearest_face_normal_error(m, clean), r.ev_relative, 100.0 * scanned_coverage(m, clean, scan.points, 2.0 * spacing),
              seconds);
}

}  // namespace

int run(int argc, char** argv) {
  namespace fs = std::filesystem;
  fs::path dir = "../shared/data/pairs";
  double voxel = 0.0;
  std::vector<std::string> models;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--voxel") && i + 1 < argc) voxel = std::atof(argv[++i]);
    else if (fs::is_directory(argv[i])) dir = argv[i];
    else models.emplace_back(argv[i]);
  }
  if (!fs::is_directory(dir)) {
    std::printf("skipped: %s not found\n", dir.c_str());
    return 0;
  }
  if (models.empty()) models = {"fandisk-0.3", "block-0.4"};
  std::printf("| model | stage | faces | normal error deg | E_v / diag | coverage | seconds (cumulative) |\n|---|---|---|---|---|---|---|\n");
  for (const auto& name : models) {
    const Mesh clean = read_mesh((dir / name / "clean.obj").string());
    const auto t0 = std::chrono::steady_clock::now();
    const PointCloud scan = merge_views(virtual_scan(clean, VirtualScanOptions{}));
    const double t_scan = since(t0);
    const auto t1 = std::chrono::steady_clock::now();
    PointCloud cloud = scan;
    CloudScale scale = measure_scale(cloud);
    if (voxel > 0.0) {
      voxel_downsample(cloud, VoxelOptions{Length::spacings(voxel)}, scale);
      scale = measure_scale(cloud);
    }
    remove_outliers(cloud, OutlierOptions{}, scale);
    estimate_normals(cloud, NormalOptions{});
    Mesh mesh = triangulate_gp3(cloud, Gp3Options{}, scale);
    clean_mesh(mesh, CleanupOptions{});
    const double t_mesh = since(t1);
    std::printf("| %-12s | %-22s | %7zu points | | | | %6.2f |\n", name.c_str(), "virtual scan (6 views)", scan.points.size(), t_scan);
    report(name.c_str(), "scanmesh mesh (gp3)", mesh, clean, scan, scale.spacing, t_mesh);
    const auto t2 = std::chrono::steady_clock::now();
    DenoiseOptions scanned;  // as the main job runs it on the meshes it makes
    scanned.scanned = true;
    scanned.vertices_are_points = true;  // greedy projection's mesh: its vertices are the points
    const AutoReport decided = denoise_auto(mesh, scanned);
    char label[64];
    std::snprintf(label, sizeof label, "+ --auto (%s, %d its)", decided.mode.c_str(), decided.run.iterations);
    std::fprintf(stderr, "%s: noise level %.3f, %s\n", name.c_str(), decided.noise_level, decided.reason.c_str());
    report(name.c_str(), label, mesh, clean, scan, scale.spacing, t_mesh + since(t2));
    // The usual alternative on the same cloud and normals: screened Poisson (PCL), depth 9, trimmed at
    // 3 spacings from the points.
    const auto t3 = std::chrono::steady_clock::now();
    PoissonOptions po;
    po.depth = 9;
    Mesh poisson = triangulate_poisson(cloud, po, scale);
    clean_mesh(poisson, CleanupOptions{});
    report(name.c_str(), "Poisson depth 9 (PCL)", poisson, clean, scan, scale.spacing, since(t3));
    std::fflush(stdout);
  }
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
