#include <chrono>
#include <cstdio>
#include <filesystem>

#include "cli_common.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/cloud_io.h"
#include "scanmesh/errors.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/parallel.h"
#include "scanmesh/combine_views.h"
#include "scanmesh/virtual_scan.h"

namespace scanmesh::cli {

int run_scan(const std::vector<std::string>& args) {
  const VirtualScanOptions d;
  po::options_description o("options");
  o.add_options()
    ("views", po::value<int>()->default_value(d.views), "viewpoints spread evenly around the mesh")
    ("width", po::value<int>()->default_value(d.width), "image columns per view")
    ("height", po::value<int>()->default_value(d.height), "image rows per view")
    ("fov", po::value<double>()->default_value(d.fov_deg), "horizontal field of view, degrees")
    ("noise", po::value<double>()->default_value(d.noise),
     "depth noise at the mean viewing distance, in mean edge lengths of the mesh; grows with depth squared")
    ("seed", po::value<unsigned long long>()->default_value(d.seed), "random seed")
    ("threads", po::value<int>()->default_value(0), "threads (0 = all cores); the output does not depend on it")
    ("quiet,q", po::bool_switch(), "print errors only");
  po::variables_map vm;
  if (!parse(args, o, {"MESH", "OUT"}, vm, "scanmesh scan MESH OUT.ply|OUT.pcd [options]",
             "Virtual depth scanner: ray-casts MESH from several viewpoints, adds depth noise along each ray, and\n"
             "writes the merged cloud to OUT and one organized cloud per view (with its viewpoint) beside it as\n"
             "OUT-view-K.pcd. Gives scans whose ground truth (MESH) is known."))
    return kOk;
  const std::string in = vm["MESH"].as<std::string>(), out = vm["OUT"].as<std::string>();
  const std::string ext = lower_extension(out);
  if (ext != ".ply" && ext != ".pcd") throw UsageError("output '" + out + "': write the merged cloud as .ply or .pcd");
  if (same_file(in, out)) throw UsageError("output '" + out + "' is the input file");
  if (vm["threads"].as<int>() < 0) throw UsageError("--threads must be >= 0");
  set_thread_count(vm["threads"].as<int>());
  VirtualScanOptions s;
  s.views = vm["views"].as<int>();
  s.width = vm["width"].as<int>();
  s.height = vm["height"].as<int>();
  s.fov_deg = vm["fov"].as<double>();
  s.noise = vm["noise"].as<double>();
  s.seed = vm["seed"].as<unsigned long long>();
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::string> warnings;
  const Mesh mesh = read_mesh(in, &warnings);
  print_warnings(warnings, vm["quiet"].as<bool>());
  const std::vector<PointCloud> views = virtual_scan(mesh, s);
  const PointCloud merged = merge_views(views);
  if (merged.points.empty()) throw InputError(in + ": no ray hit the mesh");
  const std::filesystem::path base(out);
  const std::string stem = (base.parent_path() / base.stem()).string();
  for (std::size_t v = 0; v < views.size(); ++v) write_cloud_pcd(views[v], stem + "-view-" + std::to_string(v) + ".pcd");
  if (ext == ".pcd") write_cloud_pcd(merged, out);
  else write_cloud_ply(merged, out);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!vm["quiet"].as<bool>())
    std::fprintf(stderr, "[done, %.2f s : %zu views, %zu points] -> %s and %s-view-*.pcd\n", seconds, views.size(),
                 merged.points.size(), out.c_str(), stem.c_str());
  return kOk;
}

}  // namespace scanmesh::cli
