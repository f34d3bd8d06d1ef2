// The JSON sidecar of a run (CONVENTIONS.md: version, resolved configuration, seed, threads, input
// statistics, per-stage records, metrics, histogram bins, status, problems and warnings).
#include <sys/resource.h>

#include "report_parts.h"
#include "scanmesh/json.h"
#include "scanmesh/scan_fit.h"

namespace scanmesh::detail {

std::string sidecar_json(const ReportInput& in, const ReportContent* content, const std::string& error) {
  JsonWriter w;
  w.begin_object();
  w.field("version", in.tool_version);
  w.field("status", error.empty() ? in.status : std::string("failed"));
  if (!error.empty()) w.field("error", error);
  w.key("problems").begin_array();
  for (const auto& p : in.problems) w.value(p);
  w.end_array();
  w.field("output", in.output_path).field("config", in.config_yaml).field("seed", static_cast<unsigned long long>(in.seed));
  w.field("threads", in.threads);
  w.key("input").begin_object();
  w.field("path", in.input_path).field("points", in.input_points).field("spacing", in.input_spacing).field("bbox_diagonal", in.input_diagonal);
  w.end_object();
  w.key("stages").begin_array();
  for (const auto& s : in.stages) {
    w.begin_object();
    w.field("type", s.type).field("tag", s.tag).field("seconds", s.seconds).field("peak_memory_mb", s.peak_memory_mb);
    w.field("points", s.points).field("vertices", s.vertices).field("faces", s.faces).field("details", s.details);
    w.key("options").begin_object();  // the resolved configuration: every option, given or default
    for (const auto& [k, v] : s.options) w.field(k, v);
    w.end_object();
    if (!s.decision_text.empty() || !s.decision_numbers.empty()) {
      w.key("decision").begin_object();
      for (const auto& [k, v] : s.decision_text) w.field(k, v);
      for (const auto& [k, v] : s.decision_numbers) w.field(k, v);
      w.end_object();
    }
    w.end_object();
  }
  w.end_array();
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  w.field("peak_memory_mb", static_cast<double>(u.ru_maxrss) / 1024.0);
  w.key("metrics");
  if (content && content->metrics) write_json(w, *content->metrics, in.scan_fit);
  else w.null();
  w.key("histograms").begin_object();
  if (content)
    for (const auto& h : content->histograms) {
      w.key(h.name).begin_object();
      w.field("unit", h.unit).field("lo", h.lo).field("hi", h.hi).field("mean", h.mean).field("median", h.median).field("p95", h.p95);
      w.field("max", h.max).field("clipped", h.clipped);
      w.key("counts").begin_array();
      for (std::size_t c : h.counts) w.value(c);
      w.end_array();
      w.end_object();
    }
  w.end_object();
  w.key("warnings").begin_array();
  for (const auto& s : in.warnings) w.value(s);
  w.end_array();
  w.end_object();
  return w.str();
}

}  // namespace scanmesh::detail
