#pragma once
// Quality reports a person can look at: for an output OUT.ext, OUT.report.json (the sidecar),
// OUT.report/ with PNG figures rendered by OpenCV (histograms and views of the mesh), and OUT.report.html,
// one self-contained page showing all of it. Options struct = schema of the `report` pipeline stage.
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scanmesh/atomic_file.h"
#include "scanmesh/mesh.h"
#include "scanmesh/schema.h"

namespace scanmesh {

struct ScanFit;

struct ReportOptions {
  std::string reference;
  bool figures = true;
  int image_size = 720;
  static const Schema<ReportOptions>& schema() {
    static const Schema<ReportOptions> s =
        Schema<ReportOptions>()
            .text("reference", &ReportOptions::reference, "mesh file",
                  "Ground truth to measure against (MSAE and flips need the same faces); empty = none.")
            .flag("figures", &ReportOptions::figures, "PNG figures and the HTML page; the JSON sidecar is always written.")
            .integer("image_size", &ReportOptions::image_size, closed(200, 4000), "pixels", "Rendered views are this wide and high.");
    return s;
  }
};

/// One pipeline stage as the sidecar records it.
struct StageRecord {
  std::string type, tag;
  double seconds = 0.0;
  double peak_memory_mb = 0.0;  ///< process peak resident memory after the stage
  std::size_t points = 0, vertices = 0, faces = 0;
  std::string details;          ///< e.g. the parameters --auto chose
  std::vector<std::pair<std::string, std::string>> options;  ///< every option's value (given or default)
  /// What a deciding stage (mesh.denoise with auto) measured and chose, as named values: the sidecar's
  /// "decision" object and a table in the HTML page.
  std::vector<std::pair<std::string, std::string>> decision_text;
  std::vector<std::pair<std::string, double>> decision_numbers;
};

/// Everything a report is made from. `before` is the mesh as it entered the first stage that moved its
/// vertices (for displacement), if any.
struct ReportInput {
  std::string output_path;
  std::string tool_version;
  std::string config_yaml;  ///< the resolved configuration, verbatim
  std::uint64_t seed = 0;
  int threads = 1;
  std::string input_path;
  std::size_t input_points = 0;
  double input_spacing = 0.0, input_diagonal = 0.0;
  std::vector<StageRecord> stages;
  std::vector<std::string> warnings;
  std::string status = "ok";         ///< ok, degraded or failed
  std::vector<std::string> problems;  ///< why degraded
  const ScanFit* scan_fit = nullptr;  ///< the final mesh against the points it was made from, if any
  const std::vector<Vec3>* scan_points = nullptr;  ///< those points (same order as scan_fit's distances)
  std::optional<Vec3> sensor;         ///< where the scanner was, when the input says so (views look from there)
  Vec3 sensor_up = Vec3(0, -1, 0);    ///< the sensor image's up direction in the scene (depth cameras: -y)
  const Mesh* mesh = nullptr;    ///< the final mesh (null for cloud-only pipelines)
  const Mesh* before = nullptr;  ///< the mesh before denoising, same vertex order (optional)
  const Mesh* reference = nullptr;
};

/// The paths a report writes for an output path.
struct ReportPaths {
  std::string json, folder, html;
};
inline ReportPaths report_paths(const std::string& output_path) {
  const std::filesystem::path p(output_path);
  const std::string stem = (p.parent_path() / p.stem()).string();
  return {stem + ".report.json", stem + ".report", stem + ".report.html"};
}

/// Writes the sidecar and, with options.figures, the figures and the page into `outputs` (visible when
/// the caller commits them). Returns the figure files.
std::vector<std::string> write_report(const ReportInput& input, const ReportOptions& options, OutputTransaction& outputs);

/// The vertices the report's views are framed on: the piece with most faces (pieces joined through shared
/// vertices) and every piece whose bounding box comes within a quarter of that piece's diagonal of its
/// own, so the parts of an object a scan leaves apart stay in the picture and outlying pieces do not
/// shrink it to a dot. Vertices without a finite position are left out.
std::vector<int> framed_vertices(const Mesh& mesh);

/// Writes only a sidecar with status "failed" and the error (used when a run stops on an error).
void write_failure_sidecar(const ReportInput& input, const std::string& error);

}  // namespace scanmesh
