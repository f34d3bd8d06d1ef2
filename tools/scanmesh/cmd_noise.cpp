#include <cstdio>

#include "cli_common.h"
#include "scanmesh/add_noise.h"
#include "scanmesh/mesh_io.h"

namespace scanmesh::cli {

int run_noise(const std::vector<std::string>& args) {
  po::options_description o("options");
  o.add_options()
    ("level", po::value<double>()->default_value(0.3),
     "noise standard deviation in units of the mean edge length (>= 0); 0.1 mild, 0.3 typical scan, 0.7 strong")
    ("kind", po::value<std::string>()->default_value("gaussian"),
     "gaussian, uniform (same standard deviation) or impulsive (only --fraction of the vertices move)")
    ("direction", po::value<std::string>()->default_value("random"), "random (any direction) or normal (along the vertex normal)")
    ("fraction", po::value<double>()->default_value(0.1), "share of vertices hit by impulsive noise (0..1]")
    ("seed", po::value<unsigned long long>()->default_value(1), "random seed; the same seed gives the same noise")
    ("ascii", po::bool_switch(), "write PLY/STL as text instead of binary")
    ("quiet,q", po::bool_switch(), "print errors only");
  po::variables_map vm;
  if (!parse(args, o, {"IN", "OUT"}, vm, "scanmesh noise IN OUT [options]",
             "Adds synthetic noise to a clean mesh (vertex order and faces unchanged), for experiments and tests."))
    return kOk;
  const std::string in = vm["IN"].as<std::string>(), out = vm["OUT"].as<std::string>();
  check_output_path(in, out);
  NoiseOptions n;
  n.level = vm["level"].as<double>();
  n.kind = parse_noise_kind(vm["kind"].as<std::string>());
  n.direction = parse_noise_direction(vm["direction"].as<std::string>());
  n.impulsive_fraction = vm["fraction"].as<double>();
  n.seed = vm["seed"].as<unsigned long long>();
  std::vector<std::string> warnings;
  Mesh mesh = read_mesh(in, &warnings);
  print_warnings(warnings, vm["quiet"].as<bool>());
  const double sigma = add_noise(mesh, n);
  WriteOptions w;
  w.binary = !vm["ascii"].as<bool>();
  write_mesh(mesh, out, w);
  if (!vm["quiet"].as<bool>())
    std::fprintf(stderr, "[done : %zu vertices, sigma %.6g (level %.3g x mean edge)] -> %s\n", mesh.num_vertices(), sigma,
                 n.level, out.c_str());
  return kOk;
}

}  // namespace scanmesh::cli
