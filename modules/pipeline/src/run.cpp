// Running a loaded pipeline: stages in order, one record per stage, every output committed together at
// the end (or, on failure, none and a sidecar saying why).
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <optional>

#include "pipeline_impl.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/heartbeat.h"
#include "scanmesh/parallel.h"
#include "scanmesh/report.h"
#include "scanmesh/scan_fit.h"

#ifndef SCANMESH_VERSION
#define SCANMESH_VERSION "unknown"
#endif

namespace scanmesh {

using detail::Data;
using detail::Stage;

namespace {

// The run's warnings once each, in the order first given: a file read twice (a pipeline's input that is
// also its report's reference) says the same thing twice.
std::vector<std::string> once_each(const std::vector<std::string>& warnings) {
  std::vector<std::string> out;
  for (const auto& w : warnings)
    if (std::find(out.begin(), out.end(), w) == out.end()) out.push_back(w);
  return out;
}

}  // namespace

PipelineResult Pipeline::run() {
  const auto t0 = std::chrono::steady_clock::now();
  const ThreadScope threads(impl_->options.threads);  // this run's thread count, restored afterwards
  ReportInput report;
  report.output_path = impl_->output;
  report.tool_version = SCANMESH_VERSION;
  report.config_yaml = resolved_config();
  report.threads = thread_count();
  OutputTransaction outputs;
  detail::RunContext ctx;
  ctx.options = &impl_->options;
  ctx.outputs = &outputs;
  ctx.report = &report;
  Stage* report_stage = nullptr;
  for (auto& s : impl_->slots) {
    if (s.stage->is_report()) {
      report_stage = s.stage.get();
      ctx.report_wanted = true;
    }
    if (s.where.type == "read") report.input_path += (report.input_path.empty() ? "" : ", ") + s.stage->files_read().front();
  }
  Data data;
  std::map<std::string, Data> tagged;
  PipelineResult result;
  result.output = impl_->output;
  try {
    for (auto& s : impl_->slots) s.stage->prepare(ctx);
    for (auto& s : impl_->slots) {
      if (s.inputs.size() == 1) data = tagged.at(s.inputs.front());
      const auto ts = std::chrono::steady_clock::now();
      try {
        std::optional<Heartbeat> beat;
        const auto& o = impl_->options;
        if (o.log && o.heartbeat_seconds > 0.0 && !s.stage->reports_progress())
          beat.emplace(o.heartbeat_seconds, [&o, type = s.where.type](double seconds) {
            char line[160];
            std::snprintf(line, sizeof line, "%s: still running (%.0f s)", type.c_str(), seconds);
            o.log(line);
          });
        if (s.stage->takes_many_inputs()) {
          std::vector<const Data*> ins;
          for (const auto& t : s.inputs) ins.push_back(&tagged.at(t));
          Data combined;
          s.stage->run_many(ins, combined, ctx);
          data = std::move(combined);
        } else {
          s.stage->run(data, ctx);
        }
      } catch (const Error& e) {
        // A command line's pipeline is named by its input file; a YAML pipeline's stage by FILE:LINE.
        if (impl_->path.empty() && !report.input_path.empty()) {
          const std::string what = e.what();
          // A reader's own message already starts with its file; naming it twice helps nobody.
          for (const auto& f : s.stage->files_read())
            if (what.rfind(f + ":", 0) == 0 || what.rfind("'" + f + "'", 0) == 0) throw InputError(what);
          throw InputError(report.input_path + ": " + s.where.type + ": " + what);
        }
        throw InputError(s.where.prefix() + ": " + e.what());
      }
      StageRecord rec;
      rec.type = s.where.type;
      rec.tag = s.where.tag;
      rec.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count();
      rusage u{};
      getrusage(RUSAGE_SELF, &u);
      rec.peak_memory_mb = static_cast<double>(u.ru_maxrss) / 1024.0;
      rec.points = data.cloud ? data.cloud->finite_count() : 0;
      rec.vertices = data.mesh ? data.mesh->num_vertices() : 0;
      rec.faces = data.mesh ? data.mesh->num_faces() : 0;
      rec.details = s.stage->details;
      rec.options = s.resolved;
      rec.decision_text = s.stage->decision_text;
      rec.decision_numbers = s.stage->decision_numbers;
      report.stages.push_back(rec);
      if (impl_->options.log) {
        char line[1024];
        const std::string counts = (rec.points ? std::to_string(rec.points) + " points" : std::string()) +
                                   (rec.points && rec.faces ? ", " : "") + (rec.faces ? std::to_string(rec.faces) + " faces" : std::string());
        std::snprintf(line, sizeof line, "%-16s %7.3f s  %s%s%s", rec.type.c_str(), rec.seconds, counts.c_str(), rec.details.empty() ? "" : "  ",
                      rec.details.c_str());
        impl_->options.log(line);
      }
      if (!s.where.tag.empty()) tagged[s.where.tag] = data;
    }
    // Does the mesh still represent the scan it was made from? (Measured once; the report shows it.)
    std::shared_ptr<ScanFit> fit;
    if (data.mesh && data.meshed && !data.meshed->points.empty()) {
      fit = std::make_shared<ScanFit>(measure_scan_fit(*data.mesh, data.meshed->points, data.meshed->spacing, data.meshed->from_grid,
                                                        data.meshed->fit.get()));
      for (const std::string& p : scan_fit_problems(*fit)) {
        ctx.problems.push_back(p);
        ctx.warnings.push_back("degraded: " + p);
      }
      if (impl_->options.log) impl_->options.log("scan fit: " + scan_fit_summary(*fit));
    }
    report.scan_fit = fit.get();
    result.scan_fit = fit;
    report.scan_points = fit ? &data.meshed->points : nullptr;
    if (data.cloud && data.cloud->sensor_origin) {
      report.sensor = data.cloud->sensor_origin;
      report.sensor_up = data.cloud->sensor_orientation * Vec3(0, -1, 0);
    }
    report.status = ctx.problems.empty() ? "ok" : "degraded";
    report.problems = ctx.problems;
    report.seed = data.seed;
    report.warnings = once_each(ctx.warnings);
    if (report_stage) result.report_files = report_stage->write_report(report, data, ctx);
    outputs.commit();
  } catch (const std::exception& e) {
    if (report_stage && !impl_->output.empty()) {
      report.warnings = once_each(ctx.warnings);
      try {
        report_stage->write_failure(report, e.what());
      } catch (...) {
      }
    }
    throw;
  }
  result.warnings = once_each(ctx.warnings);
  result.status = ctx.problems.empty() ? "ok" : "degraded";
  result.problems = ctx.problems;
  if (data.mesh) {
    // Counts only (no topology pass on a large mesh just for this line); the sidecar has the rest.
    result.summary = std::to_string(data.mesh->num_vertices()) + " vertices, " + std::to_string(data.mesh->num_faces()) + " faces";
    if (result.scan_fit)
      result.summary += ", " + std::to_string(result.scan_fit->loops.size()) + (result.scan_fit->loops.size() == 1 ? " boundary loop, " : " boundary loops, ") +
                        std::to_string(result.scan_fit->pieces) + (result.scan_fit->pieces == 1 ? " piece" : " pieces");
  } else if (data.cloud) {
    result.summary = std::to_string(data.cloud->finite_count()) + " points";
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace scanmesh
