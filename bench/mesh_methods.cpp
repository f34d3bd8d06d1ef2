// Which meshing method wins where. The main job (configs/scan_to_mesh.yaml, mesh.auto) against the same
// pipeline with the method fixed by hand (gp3, Poisson trimmed to the data, Poisson watertight), on
//  1. every cloud in ../shared/data/clouds (no truth): coverage of the points, holes, pieces, status, time;
//  2. sparse virtual scans of complete objects with known truth (few views, few points): normal error
//     against the clean mesh (nearest face, degrees), E_v / bounding-box diagonal, coverage, status.
// usage: scanmesh_mesh_methods [DATA_DIR] [--config configs/scan_to_mesh.yaml] [--clouds-only|--scans-only]
//                              [--set STAGE.KEY=VALUE ...]   (added to every method's run, to try a setting)
//                              [--models NAME,NAME...]  (virtual scans of these models of DATA_DIR/train instead, or
//                              of files under DATA_DIR: meshes/featuretype.stl)
//                              [--breakdown]  (virtual scans: where E_v comes from, by distance to the nearest scan point)
//                              [--main-job-only]  (the main job's rows alone: a quarter of the time, to compare builds or settings)
//                              [--views N] [--pixels WxH] [--scan-noise S]  (other virtual scans than the table's
//                              4 views of 96 x 72, noise 0.2: settings no rule was chosen on)
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <filesystem>
#include <string>
#include <vector>

#include "scanmesh/cloud_io.h"
#include "scanmesh/combine_views.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/neighbourhoods.h"
#include "scanmesh/pipeline.h"
#include "scanmesh/scan_fit.h"
#include "scanmesh/virtual_scan.h"
#include "guarded_main.h"
#include "scan_options.h"

using namespace scanmesh;
namespace fs = std::filesystem;

namespace {

struct Method {
  const char* name;
  std::vector<std::string> sets;
};

const std::vector<Method>& methods() {
  static const std::vector<Method> m = {{"auto (main job)", {}},
                                        {"gp3", {"mesh.method=gp3"}},
                                        {"poisson trimmed", {"mesh.method=poisson"}},
                                        {"poisson watertight", {"mesh.method=poisson", "mesh.watertight=true"}}};
  return m;
}

struct Outcome {
  bool ok = false;
  std::string status, error;
  std::shared_ptr<const ScanFit> fit;  // against the points as meshed (after dequantization and outlier removal)
  double seconds = 0.0;
  Mesh mesh;
};

Outcome run(const std::string& config, const std::string& input, const std::string& output, const std::vector<std::string>& sets,
            const std::vector<std::string>& extra) {
  Outcome o;
  PipelineOptions po;
  po.input = input;
  po.output = output;
  po.sets = sets;
  po.sets.insert(po.sets.end(), extra.begin(), extra.end());
  const auto t0 = std::chrono::steady_clock::now();
  try {
    const PipelineResult r = Pipeline::load(config, po).run();
    o.status = r.status;
    o.fit = r.scan_fit;
    o.mesh = read_mesh(output);
    o.ok = true;
  } catch (const std::exception& e) {
    o.error = e.what();
  }
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return o;
}

std::vector<Vec3> finite_points(const PointCloud& c) {
  std::vector<Vec3> out;
  for (const Vec3& p : c.points)
    if (p.allFinite()) out.push_back(p);
  return out;
}

// Vertices binned by their distance to the nearest scan point (in spacings): share of vertices, share of
// the sum of squared distances to the truth, and the RMS distance within the bin (/ spacing).
void print_breakdown(const std::vector<double>& to_truth, const std::vector<double>& to_scan, double spacing) {
  const double edges[] = {0.5, 1.0, 2.0, 3.0, 1e300};
  double n[5] = {}, d2[5] = {}, total = 0.0;
  for (std::size_t v = 0; v < to_truth.size(); ++v) {
    const double s = to_scan[v] / spacing;
    std::size_t b = 0;
    while (s >= edges[b] && b < 4) ++b;
    n[b] += 1.0;
    d2[b] += to_truth[v] * to_truth[v];
    total += to_truth[v] * to_truth[v];
  }
  std::printf("|   | by distance to the scan (spacings) | <0.5, 0.5-1, 1-2, 2-3, >3: vertices / share of sum d^2 / RMS d (spacings) |");
  for (int b = 0; b < 5; ++b)
    std::printf(" %.0f%%/%.0f%%/%.2f", 100.0 * n[b] / std::max<std::size_t>(1, to_truth.size()), total > 0 ? 100.0 * d2[b] / total : 0.0,
                n[b] > 0 ? std::sqrt(d2[b] / n[b]) / spacing : 0.0);
  std::printf(" |\n");
}

}  // namespace

static int run(int argc, char** argv) {
  fs::path data = "../shared/data";
  std::string config = "configs/scan_to_mesh.yaml";
  bool clouds = true, scans = true;
  std::vector<std::string> extra;
  bool breakdown = false, main_only = false;
  std::string model_list;
  VirtualScanOptions vo;  // the table's sparse scans unless asked otherwise
  vo.views = 4;
  vo.width = 96;
  vo.height = 72;
  vo.noise = 0.2;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--config") && i + 1 < argc) config = argv[++i];
    else if (!std::strcmp(argv[i], "--set") && i + 1 < argc) extra.push_back(argv[++i]);
    else if (!std::strcmp(argv[i], "--breakdown")) breakdown = true;
    else if (!std::strcmp(argv[i], "--main-job-only")) main_only = true;
    else if (!std::strcmp(argv[i], "--clouds-only")) scans = false;
    else if (!std::strcmp(argv[i], "--scans-only")) clouds = false;
    else if (!std::strcmp(argv[i], "--models") && i + 1 < argc) model_list = argv[++i];
    else if (bench::read_scan_option(i, argc, argv, vo)) continue;
    else data = argv[i];
  }
  register_scan_stages();
  // The folder the asked-for part reads: clouds/, or the models of train/ (or the shared ones) for the scans.
  const fs::path needed = clouds ? data / "clouds" : !model_list.empty() && model_list.find('.') == std::string::npos ? data / "train" : data;
  if (!fs::is_directory(needed)) {
    std::printf("skipped: %s not found\n", needed.c_str());
    return 0;
  }
  const fs::path tmp = fs::temp_directory_path() / ("scanmesh_methods_" + std::to_string(::getpid()));
  fs::create_directories(tmp);
  const std::string out = (tmp / "out.ply").string();

  if (clouds) {
    std::printf("## Real clouds (no truth): coverage = points within the coverage radius (2 spacings, or 3x their scatter across the surface) of the final mesh, of the points as meshed "
                "(dequantized, outliers removed) and of the raw file\n\n");
    std::printf("| cloud | method | status | coverage (as meshed) | coverage (raw) | holes | gaps | pieces | p95 distance | seconds |\n"
                "|---|---|---|---|---|---|---|---|---|---|\n");
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(data / "clouds"))
      if (e.is_regular_file() && holds_cloud(e.path().string())) files.push_back(e.path());
    for (const char* scan : {"bun000.ply", "bun045.ply", "bun090.ply"})
      if (fs::exists(data / "clouds" / "bunny-range-scans" / scan)) files.push_back(data / "clouds" / "bunny-range-scans" / scan);
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      const PointCloud cloud = read_cloud(f.string());
      const double spacing = measure_scale(cloud).spacing;
      for (const auto& m : methods()) {
        if (main_only && &m != &methods().front()) continue;
        if (cloud.organized() && std::string(m.name) != "auto (main job)") {
          if (std::string(m.name) != "gp3") continue;  // organized frames: auto (organized meshing) against gp3 only
        }
        const Outcome o = run(config, f.string(), out, m.sets, extra);
        if (!o.ok) {
          std::printf("| %s | %s | failed: %s | | | | | | | %.2f |\n", f.filename().c_str(), m.name, o.error.c_str(), o.seconds);
          continue;
        }
        const ScanFit fit = measure_scan_fit(o.mesh, cloud.points, spacing, cloud.organized() && std::string(m.name) == "auto (main job)");
        std::printf("| %s | %s | %s | %.2f%% | %.2f%% | %zu | %zu | %zu | %.3g | %.2f |\n", f.filename().c_str(), m.name, o.status.c_str(),
                    o.fit ? 100.0 * o.fit->coverage : 0.0, 100.0 * fit.coverage, o.fit ? o.fit->holes : fit.holes, o.fit ? o.fit->gaps : fit.gaps,
                    fit.pieces, fit.distance_p95, o.seconds);
        std::fflush(stdout);
      }
    }
  }

  if (scans) {
    std::printf("\n## Sparse virtual scans of complete objects (truth known): %d views of %d x %d pixels, noise %g\n\n", vo.views, vo.width,
                vo.height, vo.noise);
    std::printf("| model | points | method | status | normal error (deg) | E_v / diag | coverage of the scanned surface | seconds |\n"
                "|---|---|---|---|---|---|---|---|\n");
    std::vector<std::pair<std::string, fs::path>> models = {
        {"bunny", data / "pairs" / "bunny-0.2" / "clean.obj"}, {"fandisk", data / "pairs" / "fandisk-0.3" / "clean.obj"},
        {"spot", data / "train" / "spot.obj"},                 {"homer", data / "train" / "homer.obj"},
        {"rocker-arm", data / "train" / "rocker-arm.obj"},     {"cow", data / "train" / "cow.obj"}};
    if (!model_list.empty()) {  // other models of train/, e.g. to choose a setting on models the table does not show
      models.clear();
      std::stringstream names(model_list);
      for (std::string name; std::getline(names, name, ',');) {
        const fs::path as_given(name);  // a file under DATA_DIR (meshes/featuretype.stl), or a model of train/ by name
        if (as_given.has_extension()) models.emplace_back(as_given.stem().string(), data / as_given);
        else models.emplace_back(name, data / "train" / (name + ".obj"));
      }
    }
    for (const auto& [name, file] : models) {
      if (!fs::exists(file)) continue;
      const Mesh clean = read_mesh(file.string());
      const PointCloud scan = merge_views(virtual_scan(clean, vo));
      const std::string scan_file = (tmp / (name + ".ply")).string();
      write_cloud_ply(scan, scan_file);
      const double spacing = measure_scale(scan).spacing;
      for (const auto& m : methods()) {
        if (main_only && &m != &methods().front()) continue;
        const Outcome o = run(config, scan_file, out, m.sets, extra);
        if (!o.ok) {
          std::printf("| %s | %zu | %s | failed: %s | | | | %.2f |\n", name.c_str(), scan.size(), m.name, o.error.c_str(), o.seconds);
          continue;
        }
        const MeshMetrics mm = evaluate(o.mesh, &clean);
        std::printf("| %s | %zu | %s | %s | %.2f | %.3e | %.1f%% | %.2f |\n", name.c_str(), scan.size(), m.name, o.status.c_str(),
                    nearest_face_normal_error(o.mesh, clean), mm.ev_relative,
                    100.0 * scanned_coverage(o.mesh, clean, finite_points(scan), 2.0 * spacing), o.seconds);
        if (breakdown) print_breakdown(mm.vertex_distance, nearest_point_distances(finite_points(scan), o.mesh.positions), spacing);
        std::fflush(stdout);
      }
    }
  }
  fs::remove_all(tmp);
  return 0;
}

int main(int argc, char** argv) { return scanmesh::bench::guarded_main(run, argc, argv); }
