// The HTML page of a report: one self-contained file (figures embedded as data URIs).
#include <filesystem>
#include <sstream>

#include "report_parts.h"
#include "scanmesh/scan_fit.h"

namespace scanmesh::detail {
namespace {

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '&') o += "&amp;";
    else if (c == '"') o += "&quot;";
    else o += c;
  }
  return o;
}

std::string fmt(double v, int digits = 4) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

std::string base64(const std::vector<unsigned char>& data) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((data.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < data.size(); i += 3) {
    const unsigned v = (static_cast<unsigned>(data[i]) << 16) | ((i + 1 < data.size() ? data[i + 1] : 0u) << 8) |
                       (i + 2 < data.size() ? data[i + 2] : 0u);
    out += t[(v >> 18) & 63];
    out += t[(v >> 12) & 63];
    out += i + 1 < data.size() ? t[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? t[v & 63] : '=';
  }
  return out;
}

// A two-column table of name / value rows.
void rows(std::ostringstream& h, const std::vector<std::pair<std::string, std::string>>& items) {
  h << "<table class=\"kv\">\n";
  for (const auto& [k, v] : items) h << "<tr><th>" << esc(k) << "</th><td>" << esc(v) << "</td></tr>\n";
  h << "</table>\n";
}

}  // namespace

std::string html_page(const ReportInput& in, const ReportContent& c) {
  std::ostringstream h;
  const std::string name = std::filesystem::path(in.output_path).filename().string();
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>scanmesh report: " << esc(name) << "</title>\n<style>"
       "body{font-family:sans-serif;margin:24px;max-width:1700px;color:#222}figure{display:inline-block;margin:8px;vertical-align:top}"
       "figure img{max-width:100%;border:1px solid #ccc}figcaption{max-width:760px;font-size:90%;color:#444;margin-top:4px}"
       "table{border-collapse:collapse;margin:6px 0}td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}th{background:#eee}"
       "table.kv th{text-align:left}table.kv td{text-align:left}.status{font-weight:bold;padding:2px 8px;border-radius:4px}"
       ".ok{background:#cfc}.degraded{background:#fd9}.failed{background:#f99}</style></head><body>\n";
  h << "<h1>scanmesh report: " << esc(name) << "</h1>\n<p>status: <span class=\"status " << esc(in.status) << "\">" << esc(in.status)
    << "</span> &mdash; input <code>" << esc(in.input_path) << "</code> &rarr; output <code>" << esc(in.output_path) << "</code></p>\n";
  if (!in.problems.empty()) {
    h << "<h2>Problems</h2><ul>";
    for (const auto& p : in.problems) h << "<li>" << esc(p) << "</li>";
    h << "</ul>\n";
  }
  h << "<h2>Summary</h2>\n";
  std::vector<std::pair<std::string, std::string>> summary;
  if (in.input_points > 0)
    summary.push_back({"input cloud", std::to_string(in.input_points) + " points, mean spacing " + fmt(in.input_spacing) +
                                          ", bounding-box diagonal " + fmt(in.input_diagonal) + " (scene units)"});
  if (c.metrics) {
    const auto& m = *c.metrics;
    const auto& t = m.topology;
    summary.push_back({"mesh", std::to_string(t.vertices) + " vertices, " + std::to_string(t.faces) + " faces, mean edge " +
                                   fmt(m.mean_edge_length)});
    summary.push_back({"pieces", std::to_string(t.components)});
    summary.push_back({"boundary loops", std::to_string(t.boundary_loops)});
    summary.push_back({"defects", std::to_string(t.nonmanifold_edges) + " non-manifold edges, " + std::to_string(t.degenerate_faces) +
                                      " degenerate faces, " + std::to_string(t.inconsistent_edges) + " edges between faces of opposite orientation"});
    summary.push_back({"triangle quality Q", "mean " + fmt(m.quality_mean) + " (0.577 = equilateral; lower is better)"});
    if (m.has_reference) {
      if (m.same_connectivity) summary.push_back({"MSAE against the reference", fmt(m.msae_deg) + " degrees, " + std::to_string(m.flipped_faces) + " flipped faces"});
      summary.push_back({"E_v against the reference", fmt(m.ev) + " (" + fmt(m.ev_relative) + " x diagonal); Hausdorff " + fmt(m.hausdorff)});
    }
  }
  if (in.scan_fit) {
    const ScanFit& f = *in.scan_fit;
    summary.push_back({"points left out", fmt(100.0 * (1.0 - f.coverage), 3) + "% (" + std::to_string(f.points_left_out) + " of " +
                                              std::to_string(f.points) + " farther than " + fmt(f.coverage_radius) + " = " + coverage_radius_words(f) + ")"});
    summary.push_back({"cloud-to-mesh distance", "mean " + fmt(f.distance_mean) + ", 95th percentile " + fmt(f.distance_p95) + ", max " +
                                                     fmt(f.distance_max) + " (scene units)"});
    summary.push_back({"holes", std::to_string(f.holes) + " where the scan has points" +
                                    (f.holes ? " (largest " + fmt(f.largest_hole) + " around)" : std::string()) + "; " +
                                    std::to_string(f.gaps) + " gaps in the data; " + std::to_string(f.rims) + " outer rims"});
    summary.push_back({"main piece", fmt(100.0 * f.main_piece_share, 3) + "% of the faces" +
                                         (f.layered_pieces ? "; " + std::to_string(f.layered_pieces) + (f.layered_pieces == 1 ? " piece" : " pieces") +
                                                                 " with " + fmt(100.0 * f.layered_share, 3) +
                                                                 "% of the faces lying over another (the surface meshed twice)"
                                                           : std::string())});
  }
  rows(h, summary);
  for (const auto& f : c.figures)
    h << "<figure><img alt=\"" << esc(std::filesystem::path(f.file).filename().string()) << "\" src=\"data:image/png;base64," << base64(f.png)
      << "\"><figcaption><b>" << esc(f.title) << ".</b> " << esc(f.caption) << "</figcaption></figure>\n";
  h << "<h2>Stages</h2><table><tr><th>stage</th><th>tag</th><th>seconds</th><th>peak MB</th><th>points</th><th>faces</th><th>details</th></tr>\n";
  for (const auto& s : in.stages)
    h << "<tr><td style=\"text-align:left\">" << esc(s.type) << "</td><td>" << esc(s.tag) << "</td><td>" << fmt(s.seconds, 3) << "</td><td>"
      << fmt(s.peak_memory_mb) << "</td><td>" << s.points << "</td><td>" << s.faces << "</td><td style=\"text-align:left\">" << esc(s.details)
      << "</td></tr>\n";
  h << "</table>\n";
  for (const auto& s : in.stages) {
    if (s.decision_text.empty() && s.decision_numbers.empty()) continue;
    h << "<h3>Decision of " << esc(s.type) << (s.tag.empty() ? "" : " (" + esc(s.tag) + ")") << "</h3>\n";
    std::vector<std::pair<std::string, std::string>> items(s.decision_text.begin(), s.decision_text.end());
    for (const auto& [k, v] : s.decision_numbers) items.push_back({k, fmt(v)});
    rows(h, items);
  }
  if (!in.warnings.empty()) {
    h << "<h2>Warnings</h2><ul>";
    for (const auto& w : in.warnings) h << "<li>" << esc(w) << "</li>";
    h << "</ul>\n";
  }
  h << "<h2>Configuration</h2><pre>" << esc(in.config_yaml) << "</pre>\n</body></html>\n";
  return h.str();
}

}  // namespace scanmesh::detail
