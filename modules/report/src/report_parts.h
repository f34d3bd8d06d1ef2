#pragma once
// The parts of a report, inside the report module: what report.cpp measures and renders once, and the two
// documents written from it (sidecar.cpp: JSON; page.cpp: HTML).
#include <optional>
#include <string>
#include <vector>

#include "figures.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/report.h"

namespace scanmesh::detail {

struct Figure {
  std::string file;     ///< path of the PNG
  std::string title;    ///< heading on the page
  std::string caption;  ///< how to read it
  std::vector<unsigned char> png;
};

struct ReportContent {
  std::optional<MeshMetrics> metrics;
  std::vector<Histogram> histograms;
  std::vector<Figure> figures;
};

/// The sidecar: status, configuration, input, stages, metrics, scan fit, histograms, problems and
/// warnings. `content` is null for a failed run; `error` says why it failed.
std::string sidecar_json(const ReportInput& input, const ReportContent* content, const std::string& error);

/// One self-contained page: summary, problems, figures with captions, stages, decisions, configuration.
std::string html_page(const ReportInput& input, const ReportContent& content);

}  // namespace scanmesh::detail
