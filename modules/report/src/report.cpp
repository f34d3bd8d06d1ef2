// Reports: JSON sidecar (hand-written, tiny), figures rendered with OpenCV, and a self-contained HTML page.
#include "scanmesh/report.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "scanmesh/atomic_file.h"
#include "scanmesh/errors.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/geometry.h"
#include "scanmesh/topology.h"

namespace scanmesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string json_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      case '\r': o += "\\r"; break;
      case '\t': o += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char b[8];
          std::snprintf(b, sizeof b, "\\u%04x", c);
          o += b;
        } else {
          o += c;
        }
    }
  }
  return o;
}

std::string html_escape(const std::string& s) {
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

std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream o;
  o.precision(10);
  o << v;
  return o.str();
}

struct Histogram {
  std::string name, title, unit;
  double lo = 0, hi = 1;
  std::vector<std::size_t> counts;
  double mean = 0, median = 0;
  std::size_t total = 0, clipped = 0;
};

Histogram make_histogram(const std::string& name, const std::string& title, const std::string& unit, std::vector<double> values,
                         double lo, double hi, int bins) {
  Histogram h;
  h.name = name;
  h.title = title;
  h.unit = unit;
  h.lo = lo;
  h.hi = hi;
  h.counts.assign(static_cast<std::size_t>(bins), 0);
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }), values.end());
  h.total = values.size();
  if (values.empty()) return h;
  h.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  h.median = values[values.size() / 2];
  for (double v : values) {
    if (v >= hi) ++h.clipped;
    const int b = std::clamp(static_cast<int>((v - lo) / (hi - lo) * bins), 0, bins - 1);
    ++h.counts[b];
  }
  return h;
}

std::string fmt(double v, int digits = 3) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

// A bar chart with axes, ticks, labels and the mean/median marked.
cv::Mat render_histogram(const Histogram& h) {
  const int W = 760, H = 460, left = 80, right = 30, top = 72, bottom = 70;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  const int pw = W - left - right, ph = H - top - bottom;
  const std::size_t peak = std::max<std::size_t>(1, *std::max_element(h.counts.begin(), h.counts.end()));
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  cv::putText(img, h.title, {left, 30}, font, 0.6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  // Bars.
  const double bw = static_cast<double>(pw) / h.counts.size();
  for (std::size_t b = 0; b < h.counts.size(); ++b) {
    const int bh = static_cast<int>(std::round(ph * static_cast<double>(h.counts[b]) / peak));
    cv::rectangle(img, cv::Point(left + static_cast<int>(b * bw) + 1, top + ph - bh),
                  cv::Point(left + static_cast<int>((b + 1) * bw) - 1, top + ph), cv::Scalar(190, 120, 40), cv::FILLED);
  }
  // Axes and ticks.
  cv::line(img, {left, top + ph}, {left + pw, top + ph}, cv::Scalar(0, 0, 0), 1);
  cv::line(img, {left, top}, {left, top + ph}, cv::Scalar(0, 0, 0), 1);
  for (int t = 0; t <= 5; ++t) {
    const int x = left + pw * t / 5;
    cv::line(img, {x, top + ph}, {x, top + ph + 5}, cv::Scalar(0, 0, 0), 1);
    const std::string label = fmt(h.lo + (h.hi - h.lo) * t / 5.0) + (t == 5 && h.clipped ? "+" : "");
    cv::putText(img, label, {x - 14, top + ph + 22}, font, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    const int y = top + ph - ph * t / 5;
    cv::line(img, {left - 5, y}, {left, y}, cv::Scalar(0, 0, 0), 1);
    cv::putText(img, std::to_string(static_cast<long long>(std::llround(static_cast<double>(peak) * t / 5.0))), {8, y + 5}, font, 0.42,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  int baseline = 0;
  const cv::Size unit_size = cv::getTextSize(h.unit, font, 0.5, 1, &baseline);
  cv::putText(img, h.unit, {left + (pw - unit_size.width) / 2, H - 18}, font, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, "count", {8, top - 22}, font, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  // Mean and median.
  auto mark = [&](double v, const cv::Scalar& colour) {
    if (!(v >= h.lo && v <= h.hi)) return;
    const int x = left + static_cast<int>((v - h.lo) / (h.hi - h.lo) * pw);
    cv::line(img, {x, top}, {x, top + ph}, colour, 2);
  };
  mark(h.mean, cv::Scalar(0, 0, 220));
  mark(h.median, cv::Scalar(0, 160, 0));
  const std::string legend = "mean " + fmt(h.mean) + " (red)   median " + fmt(h.median) + " (green)   n = " + std::to_string(h.total);
  cv::putText(img, legend, {left, 52}, font, 0.45, cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
  return img;
}

// Orthographic, flat-shaded view from direction `eye` (unit), painter's algorithm; optional per-face colours
// (BGR, negative = shaded grey), feature edges drawn dark.
cv::Mat render_view(const Mesh& m, const Vec3& eye, const std::vector<cv::Scalar>& face_colours, const std::string& title,
                    int size, const std::vector<std::array<int, 2>>& feature_edges) {
  cv::Mat img(size, size, CV_8UC3, cv::Scalar(255, 255, 255));
  if (m.faces.empty()) return img;
  const Vec3 forward = -eye.normalized();
  const Vec3 up0 = std::abs(forward.z()) < 0.95 ? Vec3(0, 0, 1) : Vec3(0, 1, 0);
  const Vec3 right = forward.cross(up0).normalized();
  const Vec3 up = right.cross(forward);
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& p : m.positions) {
    if (!p.allFinite()) continue;
    x0 = std::min(x0, p.dot(right));
    x1 = std::max(x1, p.dot(right));
    y0 = std::min(y0, p.dot(up));
    y1 = std::max(y1, p.dot(up));
  }
  const double scale = 0.8 * size / std::max({x1 - x0, y1 - y0, 1e-300});  // room for title and colour bar
  const double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
  auto project = [&](const Vec3& p) {
    return cv::Point(static_cast<int>(std::lround(size / 2.0 + (p.dot(right) - cx) * scale)),
                     static_cast<int>(std::lround(size / 2.0 + 12 - (p.dot(up) - cy) * scale)));
  };
  std::vector<std::pair<double, int>> order;
  order.reserve(m.faces.size());
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    const Face& t = m.faces[f];
    order.emplace_back((m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]).dot(forward), static_cast<int>(f));
  }
  std::sort(order.begin(), order.end(), std::greater<>());  // far first
  const Vec3 light = (-forward + 0.4 * up + 0.3 * right).normalized();
  for (const auto& [depth, f] : order) {
    const Face& t = m.faces[f];
    const Vec3 n = triangle_normal(m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]);
    const double shade = 0.25 + 0.75 * std::abs(n.dot(light));
    cv::Scalar c = face_colours.empty() || face_colours[f][0] < 0 ? cv::Scalar(210, 210, 210) : face_colours[f];
    c = cv::Scalar(c[0] * shade, c[1] * shade, c[2] * shade);
    const cv::Point pts[3] = {project(m.positions[t[0]]), project(m.positions[t[1]]), project(m.positions[t[2]])};
    cv::fillConvexPoly(img, pts, 3, c, m.faces.size() > 100000 ? cv::LINE_8 : cv::LINE_AA);
  }
  for (const auto& [a, b] : feature_edges) cv::line(img, project(m.positions[a]), project(m.positions[b]), cv::Scalar(40, 40, 40), 1, cv::LINE_AA);
  cv::putText(img, title, {12, 26}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  return img;
}

// The turbo colour map as a 256-entry table, built once.
const std::vector<cv::Scalar>& turbo() {
  static const std::vector<cv::Scalar> table = [] {
    cv::Mat ramp(1, 256, CV_8UC1);
    for (int i = 0; i < 256; ++i) ramp.at<unsigned char>(0, i) = static_cast<unsigned char>(i);
    cv::Mat rgb;
    cv::applyColorMap(ramp, rgb, cv::COLORMAP_TURBO);
    std::vector<cv::Scalar> t(256);
    for (int i = 0; i < 256; ++i) {
      const auto v = rgb.at<cv::Vec3b>(0, i);
      t[i] = cv::Scalar(v[0], v[1], v[2]);
    }
    return t;
  }();
  return table;
}

// Colour bar legend at the bottom of a view.
void draw_colour_bar(cv::Mat& img, double lo, double hi, const std::string& unit) {
  const int x0 = 40, x1 = img.cols - 40, y = img.rows - 40;
  for (int x = x0; x < x1; ++x) cv::line(img, {x, y}, {x, y + 12}, turbo()[255 * (x - x0) / (x1 - x0)], 1);
  cv::putText(img, fmt(lo), {x0, y + 30}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, fmt(hi) + "+ " + unit, {x1 - 110, y + 30}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

std::vector<cv::Scalar> colour_map(const std::vector<double>& values, double lo, double hi) {
  std::vector<cv::Scalar> out(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double t = std::isfinite(values[i]) ? std::clamp((values[i] - lo) / (hi - lo), 0.0, 1.0) : 1.0;
    out[i] = turbo()[static_cast<int>(std::lround(255.0 * t))];
  }
  return out;
}

std::string base64(const std::vector<unsigned char>& data) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((data.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < data.size(); i += 3) {
    const unsigned v = (data[i] << 16) | ((i + 1 < data.size() ? data[i + 1] : 0) << 8) | (i + 2 < data.size() ? data[i + 2] : 0);
    out += t[(v >> 18) & 63];
    out += t[(v >> 12) & 63];
    out += i + 1 < data.size() ? t[(v >> 6) & 63] : '=';
    out += i + 2 < data.size() ? t[v & 63] : '=';
  }
  return out;
}

double peak_memory_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

std::string sidecar(const ReportInput& in, const MeshMetrics* metrics, const std::vector<Histogram>& hists,
                    const std::string& error) {
  std::ostringstream o;
  o << "{\n  \"version\": \"" << json_escape(in.tool_version) << "\",\n";
  o << "  \"status\": \"" << json_escape(error.empty() ? in.status : "failed") << "\",\n";
  if (!error.empty()) o << "  \"error\": \"" << json_escape(error) << "\",\n";
  o << "  \"output\": \"" << json_escape(in.output_path) << "\",\n";
  o << "  \"config\": \"" << json_escape(in.config_yaml) << "\",\n";
  o << "  \"seed\": " << in.seed << ",\n  \"threads\": " << in.threads << ",\n";
  o << "  \"input\": {\"path\": \"" << json_escape(in.input_path) << "\", \"points\": " << in.input_points
    << ", \"spacing\": " << num(in.input_spacing) << ", \"bbox_diagonal\": " << num(in.input_diagonal) << "},\n";
  o << "  \"stages\": [";
  for (std::size_t i = 0; i < in.stages.size(); ++i) {
    const auto& s = in.stages[i];
    o << (i ? ",\n" : "\n") << "    {\"type\": \"" << json_escape(s.type) << "\", \"tag\": \"" << json_escape(s.tag)
      << "\", \"seconds\": " << num(s.seconds) << ", \"peak_memory_mb\": " << num(s.peak_memory_mb) << ", \"points\": " << s.points
      << ", \"vertices\": " << s.vertices << ", \"faces\": " << s.faces << ", \"details\": \"" << json_escape(s.details) << "\"";
    if (!s.decision_text.empty() || !s.decision_numbers.empty()) {
      o << ", \"decision\": {";
      bool first = true;
      for (const auto& [k, v] : s.decision_text) o << (first ? "" : ", ") << "\"" << json_escape(k) << "\": \"" << json_escape(v) << "\"", first = false;
      for (const auto& [k, v] : s.decision_numbers) o << (first ? "" : ", ") << "\"" << json_escape(k) << "\": " << num(v), first = false;
      o << "}";
    }
    o << "}";
  }
  o << "\n  ],\n  \"peak_memory_mb\": " << num(peak_memory_mb()) << ",\n";
  o << "  \"metrics\": ";
  if (metrics) {
    std::string m = metrics_json(*metrics, 2);
    // Indent the nested object by two more spaces.
    std::string indented;
    for (char c : m) {
      indented += c;
      if (c == '\n') indented += "  ";
    }
    while (!indented.empty() && (indented.back() == ' ' || indented.back() == '\n')) indented.pop_back();
    o << indented;
  } else {
    o << "null";
  }
  o << ",\n  \"histograms\": {";
  for (std::size_t i = 0; i < hists.size(); ++i) {
    const auto& h = hists[i];
    o << (i ? ",\n" : "\n") << "    \"" << h.name << "\": {\"unit\": \"" << json_escape(h.unit) << "\", \"lo\": " << num(h.lo)
      << ", \"hi\": " << num(h.hi) << ", \"mean\": " << num(h.mean) << ", \"median\": " << num(h.median) << ", \"counts\": [";
    for (std::size_t b = 0; b < h.counts.size(); ++b) o << (b ? ", " : "") << h.counts[b];
    o << "]}";
  }
  o << "\n  },\n  \"warnings\": [";
  for (std::size_t i = 0; i < in.warnings.size(); ++i) o << (i ? ", " : "") << "\"" << json_escape(in.warnings[i]) << "\"";
  o << "]\n}\n";
  return o.str();
}

}  // namespace

ReportPaths report_paths(const std::string& output_path) {
  std::filesystem::path p(output_path);
  const std::string stem = (p.parent_path() / p.stem()).string();
  return {stem + ".report.json", stem + ".report", stem + ".report.html"};
}

void write_failure_sidecar(const ReportInput& input, const std::string& error) {
  write_file_atomically(report_paths(input.output_path).json, sidecar(input, nullptr, {}, error));
}

std::vector<std::string> write_report(const ReportInput& in, const ReportOptions& options, OutputTransaction& outputs) {
  const ReportPaths paths = report_paths(in.output_path);
  std::vector<Histogram> hists;
  std::optional<MeshMetrics> metrics;
  std::vector<std::string> figures;
  std::vector<std::string> pngs;  // the figures' bytes, embedded in the page
  if (in.mesh != nullptr) {
    const Mesh& m = *in.mesh;
    metrics = evaluate(m, in.reference);
    hists.push_back(make_histogram("triangle_quality", "Triangle quality Q = circumradius / shortest edge",
                                   "Q (0.577 = equilateral; lower is better)", metrics->face_quality, 0.5, 2.5, 40));
    const Topology topo = build_topology(m);
    FaceGeometry g;
    compute_face_geometry(m.positions, m.faces, g);
    std::vector<double> dihedral;
    std::vector<std::array<int, 2>> features;
    for (std::size_t e = 0; e < topo.edges.size(); ++e) {
      if (topo.edge_faces.size(e) != 2) continue;
      const int a = topo.edge_faces.begin(e)[0], b = topo.edge_faces.begin(e)[1];
      const double angle = std::acos(std::clamp(g.normals[a].dot(g.normals[b]), -1.0, 1.0)) * 180.0 / kPi;
      dihedral.push_back(angle);
      if (angle > 40.0) features.push_back(topo.edges[e]);
    }
    hists.push_back(make_histogram("dihedral_angles", "Angle between the normals of adjacent faces (0 = flat)",
                                   "degrees", dihedral, 0.0, 180.0, 36));
    const double edge = metrics->mean_edge_length > 0 ? metrics->mean_edge_length : 1.0;
    std::vector<double> displacement;
    if (in.before != nullptr && in.before->num_vertices() == m.num_vertices()) {
      for (std::size_t v = 0; v < m.num_vertices(); ++v) displacement.push_back((m.positions[v] - in.before->positions[v]).norm() / edge);
      hists.push_back(make_histogram("vertex_displacement", "How far denoising moved each vertex", "mean edge lengths",
                                     displacement, 0.0, 1.0, 40));
    }
    if (metrics->same_connectivity)
      hists.push_back(make_histogram("normal_error", "Face normal error against the reference", "degrees",
                                     metrics->face_angle_error, 0.0, 30.0, 30));
    if (options.figures) {
      std::error_code ec;
      std::filesystem::create_directories(paths.folder, ec);
      if (ec) throw OutputError("cannot create '" + paths.folder + "': " + ec.message());
      auto save = [&](const std::string& name, const cv::Mat& img) {
        std::vector<unsigned char> png;
        cv::imencode(".png", img, png);
        const std::string file = (std::filesystem::path(paths.folder) / name).string();
        pngs.emplace_back(png.begin(), png.end());
        outputs.write(file, pngs.back());
        figures.push_back(file);
      };
      for (const auto& h : hists) save(h.name + ".png", render_histogram(h));
      // Look along the area-weighted mean normal when the surface mostly faces one way (a scan seen from
      // its sensor); closed objects, whose normals cancel, get a fixed three-quarter view.
      Vec3 mean_normal = Vec3::Zero();
      double area = 0.0;
      for (std::size_t f = 0; f < m.num_faces(); ++f) {
        mean_normal += g.areas[f] * g.normals[f];
        area += g.areas[f];
      }
      const Vec3 eye = area > 0.0 && mean_normal.norm() > 0.5 * area ? Vec3((mean_normal.normalized() + Vec3(0.15, -0.2, 0.1)).normalized())
                                                                      : Vec3(Vec3(1.0, -1.3, 0.9).normalized());
      // Feature edges help on CAD-like parts; on noisy scans most edges would qualify and hide the surface.
      const bool draw_features = features.size() < topo.edges.size() / 20;
      std::vector<cv::Scalar> colours(m.num_faces(), cv::Scalar(-1, -1, -1));
      std::size_t flipped = 0;
      if (metrics->same_connectivity)
        for (std::size_t f = 0; f < m.num_faces(); ++f)
          if (metrics->face_angle_error[f] > 90.0) {
            colours[f] = cv::Scalar(40, 40, 230);
            ++flipped;
          }
      if (in.before != nullptr && in.before->faces.size() == m.faces.size())
        save("view_before.png", render_view(*in.before, eye, {}, "before (input mesh)", options.image_size, {}));
      const std::string edges_note = draw_features ? "feature edges (> 40 deg) dark"
                                                   : "feature edges omitted (" + std::to_string(100 * features.size() / std::max<std::size_t>(1, topo.edges.size())) + "% of edges > 40 deg)";
      save("view_after.png", render_view(m, eye, colours,
                                         "after: " + edges_note + (metrics->same_connectivity ? ", flipped faces red (" + std::to_string(flipped) + ")" : ""),
                                         options.image_size, draw_features ? features : std::vector<std::array<int, 2>>{}));
      if (metrics->same_connectivity) {
        cv::Mat img = render_view(m, eye, colour_map(metrics->face_angle_error, 0.0, 20.0), "normal error against the reference",
                                  options.image_size, {});
        draw_colour_bar(img, 0.0, 20.0, "deg");
        save("view_error.png", img);
      } else if (!displacement.empty()) {
        std::vector<double> per_face(m.num_faces());
        for (std::size_t f = 0; f < m.num_faces(); ++f)
          per_face[f] = (displacement[m.faces[f][0]] + displacement[m.faces[f][1]] + displacement[m.faces[f][2]]) / 3.0;
        cv::Mat img = render_view(m, eye, colour_map(per_face, 0.0, 0.5), "vertex displacement by denoising", options.image_size, {});
        draw_colour_bar(img, 0.0, 0.5, "edges");
        save("view_displacement.png", img);
      }
    }
  }
  outputs.write(paths.json, sidecar(in, metrics ? &*metrics : nullptr, hists, ""));
  if (options.figures) {
    std::ostringstream h;
    h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>scanmesh report: " << std::filesystem::path(in.output_path).filename().string()
      << "</title>\n<style>body{font-family:sans-serif;margin:24px;max-width:1600px}img{max-width:760px;margin:6px;border:1px solid #ccc}"
         "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}th{background:#eee}</style></head><body>\n";
    h << "<h1>scanmesh report</h1>\n<p>output: <code>" << html_escape(in.output_path) << "</code> &mdash; status: <b>" << in.status
      << "</b> &mdash; input: <code>" << html_escape(in.input_path) << "</code></p>\n";
    if (metrics) {
      const auto& t = metrics->topology;
      h << "<h2>Summary</h2><table><tr><th>vertices</th><th>faces</th><th>boundary loops</th><th>non-manifold edges</th><th>components</th>"
           "<th>degenerate faces</th><th>Q mean</th>";
      if (metrics->has_reference) h << "<th>MSAE (deg)</th><th>flips</th><th>E_v / diag</th><th>Hausdorff</th>";
      h << "</tr><tr><td>" << t.vertices << "</td><td>" << t.faces << "</td><td>" << t.boundary_loops << "</td><td>" << t.nonmanifold_edges
        << "</td><td>" << t.components << "</td><td>" << t.degenerate_faces << "</td><td>" << fmt(metrics->quality_mean, 4) << "</td>";
      if (metrics->has_reference)
        h << "<td>" << (metrics->same_connectivity ? fmt(metrics->msae_deg, 4) : "-") << "</td><td>"
          << (metrics->same_connectivity ? std::to_string(metrics->flipped_faces) : "-") << "</td><td>" << fmt(metrics->ev_relative, 4)
          << "</td><td>" << fmt(metrics->hausdorff, 4) << "</td>";
      h << "</tr></table>\n";
    }
    h << "<h2>Stages</h2><table><tr><th>stage</th><th>tag</th><th>seconds</th><th>peak MB</th><th>points</th><th>faces</th><th>details</th></tr>\n";
    for (const auto& s : in.stages)
      h << "<tr><td style=\"text-align:left\">" << s.type << "</td><td>" << s.tag << "</td><td>" << fmt(s.seconds, 3) << "</td><td>"
        << fmt(s.peak_memory_mb, 4) << "</td><td>" << s.points << "</td><td>" << s.faces << "</td><td style=\"text-align:left\">" << html_escape(s.details)
        << "</td></tr>\n";
    h << "</table>\n";
    for (const auto& s : in.stages) {
      if (s.decision_text.empty() && s.decision_numbers.empty()) continue;
      h << "<h2>Decision of " << html_escape(s.type) << (s.tag.empty() ? "" : " (" + html_escape(s.tag) + ")") << "</h2><table>\n";
      for (const auto& [k, v] : s.decision_text)
        h << "<tr><th style=\"text-align:left\">" << html_escape(k) << "</th><td style=\"text-align:left\">" << html_escape(v) << "</td></tr>\n";
      for (const auto& [k, v] : s.decision_numbers)
        h << "<tr><th style=\"text-align:left\">" << html_escape(k) << "</th><td style=\"text-align:left\">" << fmt(v, 4) << "</td></tr>\n";
      h << "</table>\n";
    }
    h << "<h2>Configuration</h2><pre>" << html_escape(in.config_yaml) << "</pre>\n<h2>Figures</h2>\n";
    for (std::size_t k = 0; k < figures.size(); ++k)
      h << "<img alt=\"" << std::filesystem::path(figures[k]).filename().string() << "\" src=\"data:image/png;base64,"
        << base64(std::vector<unsigned char>(pngs[k].begin(), pngs[k].end())) << "\">\n";
    if (!in.warnings.empty()) {
      h << "<h2>Warnings</h2><ul>";
      for (const auto& w : in.warnings) h << "<li>" << html_escape(w) << "</li>";
      h << "</ul>\n";
    }
    h << "</body></html>\n";
    outputs.write(paths.html, h.str());
  }
  return figures;
}

}  // namespace scanmesh
