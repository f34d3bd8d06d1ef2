#include <chrono>
#include <cstdio>

#include "cli_common.h"
#include "scanmesh/clean_cloud.h"
#include "scanmesh/clean_mesh.h"
#include "scanmesh/errors.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/parallel.h"
#include "scanmesh/cloud_io.h"
#include "scanmesh/mesh_cloud.h"

namespace scanmesh::cli {
namespace {

class StageClock {
 public:
  explicit StageClock(bool quiet) : quiet_(quiet) {}
  void done(const char* stage, const std::string& what) {
    const auto now = std::chrono::steady_clock::now();
    if (!quiet_)
      std::fprintf(stderr, "%-9s %7.3f s  %s\n", stage, std::chrono::duration<double>(now - last_).count(), what.c_str());
    last_ = now;
  }

 private:
  bool quiet_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace

int run_mesh(const std::vector<std::string>& args) {
  po::options_description o("options (lengths: a number in scene units, N*spacing = N x mean point spacing, or N% of the bounding-box diagonal)");
  o.add_options()
    ("method", po::value<std::string>()->default_value("auto"),
     "auto (organized for organized clouds, else gp3), gp3 (greedy projection: keeps the measured points as "
     "vertices), organized (grid clouds), poisson (smooth, new vertices)")
    ("voxel", po::value<std::string>()->default_value("0"), "voxel-grid leaf size; 0 = keep every point")
    ("outlier-ratio", po::value<double>()->default_value(3.0),
     "statistical outlier removal: drop points whose mean distance to their neighbours exceeds mean + ratio x std (0 = off)")
    ("outlier-neighbours", po::value<int>()->default_value(16), "neighbours for the outlier statistics")
    ("normals-k", po::value<int>()->default_value(20), "neighbours for normal estimation")
    ("keep-normals", po::bool_switch(), "use the normals stored in the file instead of estimating them")
    ("radius", po::value<std::string>()->default_value("5*spacing"), "gp3: longest edge a triangle may have")
    ("max-edge", po::value<std::string>()->default_value("6*spacing"), "organized: longest edge (larger depth jumps are not bridged)")
    ("depth", po::value<int>()->default_value(0), "poisson: octree depth (4..12; 0 = from the point spacing)")
    ("trim", po::value<std::string>()->default_value("3*spacing"), "poisson: drop surface farther than this from the points")
    ("watertight", po::bool_switch(), "poisson: keep the closed surface")
    ("min-component", po::value<int>()->default_value(10), "remove pieces with fewer faces (0 = keep all)")
    ("threads", po::value<int>()->default_value(0), "threads (0 = all cores)")
    ("ascii", po::bool_switch(), "write PLY/STL as text")
    ("quiet,q", po::bool_switch(), "print errors only");
  po::variables_map vm;
  if (!parse(args, o, {"CLOUD", "OUT"}, vm, "scanmesh mesh CLOUD OUT [options]",
             "Turns a scanner point cloud (.pcd .ply .xyz) into a triangle mesh: read, remove outliers, estimate\n"
             "normals (towards the sensor when the file knows it), triangulate, clean up (degenerate and duplicate\n"
             "faces, non-manifold edges and vertices, tiny pieces, consistent orientation)."))
    return kOk;
  const std::string in = vm["CLOUD"].as<std::string>(), out = vm["OUT"].as<std::string>();
  const bool quiet = vm["quiet"].as<bool>();
  check_output_path(in, out);
  if (vm["threads"].as<int>() < 0) throw UsageError("--threads must be >= 0");
  set_thread_count(vm["threads"].as<int>());
  const std::string method = vm["method"].as<std::string>();
  if (method != "auto" && method != "gp3" && method != "organized" && method != "poisson")
    throw UsageError("unknown --method '" + method + "'; choose auto, gp3, organized or poisson");
  VoxelOptions voxel{parse_length(vm["voxel"].as<std::string>(), "--voxel")};
  Gp3Options gp3;
  gp3.radius = parse_length(vm["radius"].as<std::string>(), "--radius");
  OrganizedOptions organized;
  organized.max_edge = parse_length(vm["max-edge"].as<std::string>(), "--max-edge");
  PoissonOptions poisson;
  poisson.depth = vm["depth"].as<int>();
  poisson.trim_distance = parse_length(vm["trim"].as<std::string>(), "--trim");
  poisson.watertight = vm["watertight"].as<bool>();
  CleanupOptions cleanup;
  cleanup.min_component_faces = vm["min-component"].as<int>();

  const auto t0 = std::chrono::steady_clock::now();
  StageClock clock(quiet);
  std::vector<std::string> warnings;
  PointCloud cloud = read_cloud(in, &warnings);
  print_warnings(warnings, quiet);
  const std::size_t points_in = cloud.finite_count();
  clock.done("read", std::to_string(points_in) + " points" + (cloud.organized() ? " (organized " + std::to_string(cloud.width) + "x" + std::to_string(cloud.height) + ")" : ""));
  const CloudScale scale = measure_scale(cloud);
  char scale_line[96];
  std::snprintf(scale_line, sizeof scale_line, "mean point spacing %.4g, bounding-box diagonal %.4g", scale.spacing, scale.diagonal);
  clock.done("scale", scale_line);
  if (voxel.leaf.value > 0.0) {
    voxel_downsample(cloud, voxel, scale);
    clock.done("voxel", std::to_string(cloud.size()) + " points");
  }
  if (vm["outlier-ratio"].as<double>() > 0.0) {
    OutlierOptions oo;
    oo.std_ratio = vm["outlier-ratio"].as<double>();
    oo.neighbours = vm["outlier-neighbours"].as<int>();
    remove_outliers(cloud, oo, scale);
    clock.done("outliers", std::to_string(points_in - cloud.finite_count()) + " removed");
  }
  const bool organized_method = method == "organized" || (method == "auto" && cloud.organized());
  if (!organized_method && !(vm["keep-normals"].as<bool>() && cloud.has_normals())) {
    NormalOptions no;
    no.neighbours = vm["normals-k"].as<int>();
    estimate_normals(cloud, no);
    clock.done("normals", cloud.sensor_origin ? "oriented towards the sensor" : "oriented by propagation");
  }
  MeshMethodOptions mo;
  MeshMethodOptions::schema().find("method")->set(mo, method);
  MeshingDecision decision;
  Mesh mesh = mesh_cloud(cloud, mo, gp3, organized, poisson, scale, &decision);
  clock.done(method_name(decision.method), std::to_string(mesh.num_faces()) + " faces: " + decision.reason);
  if (mesh.faces.empty()) throw InputError(in + ": meshing produced no triangles (too few points, or try a larger --radius)");
  const CleanupReport cr = clean_mesh(mesh, cleanup, cloud.sensor_origin);
  clock.done("cleanup", std::to_string(cr.degenerate_faces + cr.duplicate_faces + cr.nonmanifold_faces + cr.small_component_faces) +
                            " faces removed, " + std::to_string(cr.split_vertices) + " vertices split, " + std::to_string(cr.flipped_faces) + " flipped");
  if (mesh.faces.empty()) throw InputError(in + ": no triangles left after clean-up");
  WriteOptions w;
  w.binary = !vm["ascii"].as<bool>();
  write_mesh(mesh, out, w);
  const TopologyStats t = topology_stats(mesh);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!quiet)
    std::fprintf(stderr, "[done, %.2f s : %zu points -> %zu vertices, %zu faces, %zu boundary loops, %zu components] -> %s\n", seconds,
                 points_in, mesh.num_vertices(), mesh.num_faces(), t.boundary_loops, t.components, out.c_str());
  return kOk;
}

}  // namespace scanmesh::cli
