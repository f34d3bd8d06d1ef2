#include <chrono>
#include <cstdio>
#include <iostream>

#include "cli_common.h"
#include "scanmesh/denoise.h"
#include "scanmesh/errors.h"
#include "scanmesh/auto_denoise.h"
#include "scanmesh/noise_analysis.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/parallel.h"

namespace scanmesh::cli {

int run_denoise(const std::vector<std::string>& args) {
  const DenoiseOptions defaults;
  po::options_description o("options");
  o.add_options()
    ("sigma-s", po::value<double>(),
     "similarity kernel width sigma_s on |n_i - n_j| (unitless, 0 < s <= 2; default 0.45). Smaller keeps "
     "more features and more noise, larger smooths more and rounds edges. CAD 0.3-0.6, organic 0.6-1")
    ("lambda", po::value<double>(),
     "fidelity weight lambda_I (0..1; default 0.2). Evens out triangles, prevents flips under strong "
     "noise; too large shrinks and blurs. Decays by --decay each iteration")
    ("iterations", po::value<int>(),
     "iterations p (>= 0; default 60). More removes more noise; too many over-smooth organic shapes")
    ("auto", po::bool_switch(),
     "estimate the noise level and features of the mesh and choose sigma_s, lambda, iterations (and the "
     "radius factor) from them; explicitly given values still win")
    ("decay", po::value<double>()->default_value(defaults.decay), "lambda_I <- decay * lambda_I per iteration (0..1)")
    ("radius-factor", po::value<double>()->default_value(defaults.radius_factor),
     "neighbourhood radius in units of c_a, the mean distance between adjacent face centroids (0.5..10)")
    ("estimator", po::value<std::string>()->default_value("tukey"),
     "robust similarity weight: tukey (stops diffusion across features), gaussian, huber, lorentzian")
    ("neighbourhood", po::value<std::string>()->default_value("ball"),
     "ball (all faces within the radius) or connected_ball (only through adjacent faces: thin parts do not mix)")
    ("recompute-neighbourhoods", po::bool_switch(), "rebuild neighbourhoods every iteration (slower)")
    ("free-boundary", po::bool_switch(), "let boundary vertices move like interior ones (they drift inwards)")
    ("boundary-window", po::value<double>()->default_value(defaults.boundary_window),
     "width of the boundary-curve fit, in mean boundary edge lengths (0.5..10); wider smooths boundaries more")
    ("feature-aware-fidelity", po::bool_switch(),
     "fidelity term that moves vertices only along sharp edges, not across them (keeps clean CAD parts exact; "
     "measured worse on noisy fandisk)")
    ("threads", po::value<int>()->default_value(0), "threads (0 = all cores); the output does not depend on it")
    ("ascii", po::bool_switch(), "write PLY/STL as text instead of binary")
    ("quiet,q", po::bool_switch(), "print errors only");
  po::variables_map vm;
  if (!parse(args, o, {"IN", "OUT"}, vm, "scanmesh denoise IN OUT [options]",
             "Removes scanner noise from a triangle mesh while keeping sharp features, boundaries and volume\n"
             "(robust two-stage denoising, Yadav, Reitebuch, Polthier 2019). Vertex order and connectivity are\n"
             "kept, so OUT compares face by face with IN. Without parameters the documented defaults apply;\n"
             "--auto adapts them to the mesh's noise level."))
    return kOk;
  const std::string in = vm["IN"].as<std::string>(), out = vm["OUT"].as<std::string>();
  const bool quiet = vm["quiet"].as<bool>();
  check_output_path(in, out);
  set_thread_count(vm["threads"].as<int>());
  if (vm["threads"].as<int>() < 0) throw UsageError("--threads must be >= 0");

  DenoiseOptions options;
  options.decay = vm["decay"].as<double>();
  options.radius_factor = vm["radius-factor"].as<double>();
  options.estimator = parse_estimator(vm["estimator"].as<std::string>());
  options.neighbourhood = parse_neighbourhood(vm["neighbourhood"].as<std::string>());
  options.recompute_neighbourhoods = vm["recompute-neighbourhoods"].as<bool>();
  options.keep_boundary = !vm["free-boundary"].as<bool>();
  options.boundary_window = vm["boundary-window"].as<double>();
  options.feature_aware_fidelity = vm["feature-aware-fidelity"].as<bool>();
  validate(options);  // fail on bad usage before reading a large file

  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::string> warnings;
  Mesh mesh = read_mesh(in, &warnings);
  print_warnings(warnings, quiet);

  std::vector<std::string> given;
  if (vm.count("sigma-s")) options.sigma_s = vm["sigma-s"].as<double>(), given.push_back("sigma_s");
  if (vm.count("lambda")) options.lambda = vm["lambda"].as<double>(), given.push_back("lambda");
  if (vm.count("iterations")) options.iterations = vm["iterations"].as<int>(), given.push_back("iterations");
  if (!vm["radius-factor"].defaulted()) given.push_back("radius_factor");
  validate(options);
  Progress progress("denoise", quiet);
  DenoiseReport report;
  if (vm["auto"].as<bool>()) {
    const AutoReport a = denoise_auto(mesh, options, given, {}, [&](int d, int t) { progress(d, t); });
    report = a.run;
    options = a.options;
    if (!quiet)
      std::fprintf(stderr, "auto: noise %.3f x mean edge; %s: %s -> sigma_s %.3g, lambda %.3g, %d iterations (%s), radius factor %.3g; check: %s\n",
                   a.noise_level, a.mode.c_str(), a.reason.c_str(), options.sigma_s, options.lambda, report.iterations,
                   report.stop_reason.c_str(), options.radius_factor, a.check.c_str());
    if (a.check != "passed" && a.check != "not needed")
      std::fprintf(stderr, "warning: '%s': the result check ended --auto early (%s); the last iteration that passed was written\n",
                   in.c_str(), a.check.c_str());
  } else {
    if (!quiet) {
      const double plane = analyse_noise(mesh).exact_plane_fraction;
      if (plane >= 0.1)
        std::fprintf(stderr, "warning: %.0f%% of the vertices of '%s' lie exactly in the plane of their faces: it looks "
                             "noise-free (a CAD tessellation?); denoising may only disturb its triangles (--auto would "
                             "leave it alone)\n", 100.0 * plane, in.c_str());
    }
    report = denoise(mesh, options, [&](int d, int t) { progress(d, t); });
  }
  WriteOptions w;
  w.binary = !vm["ascii"].as<bool>();
  write_mesh(mesh, out, w);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!quiet)
    std::fprintf(stderr, "[done, %.3f s : %zu vertices, %zu faces, %d iterations (sigma_s %.3g, lambda %.3g), %zu boundary vertices] -> %s\n",
                 seconds, mesh.num_vertices(), mesh.num_faces(), report.iterations, options.sigma_s, options.lambda,
                 report.boundary_vertices, out.c_str());
  return kOk;
}

}  // namespace scanmesh::cli
