#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "cli_common.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/pipeline.h"
#include "scanmesh/report.h"

namespace scanmesh::cli {

int run_pipeline(const std::vector<std::string>& args) {
  po::options_description o("options");
  o.add_options()
    ("input", po::value<std::string>(), "replaces the pipeline's first reader (its input file)")
    ("output", po::value<std::string>(), "replaces the pipeline's last writer (its output file)")
    ("set", po::value<std::vector<std::string>>()->composing(),
     "TAG.OPTION=VALUE: override a stage option (repeatable); a stage's type works as TAG when it is unique")
    ("validate", po::bool_switch(), "check the pipeline (syntax, stages, options, files) without running it")
    ("strict", po::bool_switch(), "exit with code 1 when the result is degraded (written, but the mesh leaves points of "
     "its scan out, has holes where the scan has data, or faces of opposite orientation); the sidecar says why")
    ("skip-existing", po::bool_switch(), "do nothing if the output exists and its report sidecar (if any) says status ok")
    ("threads", po::value<int>()->default_value(0), "threads (0 = all cores); outputs do not depend on it")
    ("quiet,q", po::bool_switch(), "print errors only");
  po::variables_map vm;
  std::string types;
  for (const auto& t : stage_types()) types += (types.empty() ? "" : ", ") + t;
  if (!parse(args, o, {"PIPELINE"}, vm, "scanmesh run PIPELINE.yaml [options]",
             "Runs a YAML pipeline (PDAL-style): a 'pipeline:' list whose first bare file name is the reader and last\n"
             "the writer; stages are maps with 'type' (" + types + "), optional 'tag' and 'inputs' (the tags of earlier\n"
             "stages to take data from; cloud.merge and cloud.register take several); other keys are the stage's\n"
             "options (scanmesh options TYPE lists them; a key is the command-line flag with '_' for '-'). A run whose\n"
             "mesh falls short of its scan is written with status 'degraded' in its sidecar (exit 1 with --strict).\n"
             "Exit codes: 0 ok (or skipped), 1 failed on the data, 2 bad configuration (the message names FILE:LINE,\n"
             "the stage, the key and the valid choices)."))
    return kOk;
  const bool quiet = vm["quiet"].as<bool>();
  if (vm["threads"].as<int>() < 0) throw UsageError("--threads must be >= 0");
  PipelineOptions options;
  if (vm.count("input")) options.input = vm["input"].as<std::string>();
  if (vm.count("output")) options.output = vm["output"].as<std::string>();
  if (vm.count("set")) options.sets = vm["set"].as<std::vector<std::string>>();
  options.threads = vm["threads"].as<int>();
  std::unique_ptr<Progress> bar;
  if (!quiet) {
    options.progress = [&bar](const std::string& stage, int done, int total) {
      if (!bar) bar = std::make_unique<Progress>(stage, false);
      (*bar)(done, total);
      if (done == total) bar.reset();
    };
    options.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  }
  Pipeline pipeline = Pipeline::load(vm["PIPELINE"].as<std::string>(), options);
  if (vm["validate"].as<bool>()) {
    if (!quiet) std::fprintf(stderr, "%s: valid; output %s\n", vm["PIPELINE"].as<std::string>().c_str(), pipeline.output().c_str());
    return kOk;
  }
  if (vm["skip-existing"].as<bool>() && !pipeline.output().empty() && std::filesystem::exists(pipeline.output())) {
    bool ok = true;
    if (pipeline.has_report()) {
      const std::string json = report_paths(pipeline.output()).json;
      ok = std::filesystem::exists(json) && read_file(json).find("\"status\": \"ok\"") != std::string::npos;
    }
    if (ok) {
      if (!quiet) std::fprintf(stderr, "skipped: %s exists\n", pipeline.output().c_str());
      return kOk;
    }
  }
  const PipelineResult r = pipeline.run();
  // The stages' warnings (also in the sidecar); the scan-fit problems among them are printed below, also
  // under --quiet.
  std::vector<std::string> warnings;
  for (const auto& w : r.warnings)
    if (w.rfind("degraded: ", 0) != 0) warnings.push_back(w);
  print_warnings(warnings, quiet);
  if (r.status != "ok") {
    for (const auto& p : r.problems) std::fprintf(stderr, "degraded: %s\n", p.c_str());
    if (vm["strict"].as<bool>()) {
      std::fprintf(stderr, "scanmesh run: error: the result is %s (--strict); written to %s\n", r.status.c_str(), r.output.c_str());
      return kBadInput;
    }
  }
  if (!quiet) {
    std::fprintf(stderr, "[done, %.2f s] -> %s\n", r.seconds, r.output.c_str());
    if (!r.report_files.empty()) {
      const ReportPaths p = report_paths(r.output);
      std::fprintf(stderr, "report: %s (page), %s (sidecar), %s/ (%zu figures)\n", p.html.c_str(), p.json.c_str(), p.folder.c_str(),
                   r.report_files.size() >= 2 ? r.report_files.size() - 2 : 0);
    }
  }
  return kOk;
}

}  // namespace scanmesh::cli
