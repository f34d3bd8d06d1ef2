// Figures rendered with OpenCV: bar charts and orthographic flat-shaded views (painter's algorithm).
#include "figures.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "scanmesh/geometry.h"

namespace scanmesh::detail {
namespace {

const int kFont = cv::FONT_HERSHEY_SIMPLEX;

std::string fmt(double v, int digits = 3) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

std::vector<unsigned char> png(const cv::Mat& img) {
  std::vector<unsigned char> out;
  cv::imencode(".png", img, out);
  return out;
}

// The turbo colour map as a 256-entry table (BGR), built once.
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

cv::Scalar colour_of(double v, const ColourScale& s) {
  const double t = std::isfinite(v) ? std::clamp((v - s.lo) / (s.hi - s.lo), 0.0, 1.0) : 1.0;
  return turbo()[static_cast<int>(std::lround(255.0 * t))];
}

void draw_colour_bar(cv::Mat& img, int y, const ColourScale& s) {
  const int x0 = 60, x1 = img.cols - 60;
  for (int x = x0; x < x1; ++x) cv::line(img, {x, y}, {x, y + 14}, turbo()[255 * (x - x0) / (x1 - x0)], 1);
  cv::putText(img, fmt(s.lo), {x0 - 10, y + 34}, kFont, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, fmt(0.5 * (s.lo + s.hi)), {(x0 + x1) / 2 - 20, y + 34}, kFont, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  const std::string right = fmt(s.hi) + " or more";
  cv::putText(img, right, {x1 - 90, y + 34}, kFont, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, s.unit, {x0, y + 56}, kFont, 0.5, cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
}

void render_panel(cv::Mat& img, const Panel& p, const Camera& cam, const std::optional<ColourScale>& scale) {
  const int size = img.cols;
  const Vec3 forward = cam.forward.normalized();
  const Vec3 right = forward.cross(cam.up).normalized();
  const Vec3 up = right.cross(forward);
  const double scale_px = 0.86 * size / std::max(cam.extent, 1e-300);
  const double cx = cam.perspective ? cam.centre_u : cam.centre.dot(right), cy = cam.perspective ? cam.centre_v : cam.centre.dot(up);
  auto project = [&](const Vec3& q) {
    double u = q.dot(right), v = q.dot(up);
    if (cam.perspective) {
      const Vec3 d = q - cam.eye;
      const double z = std::max(d.dot(forward), 1e-12);
      u = d.dot(right) / z;
      v = d.dot(up) / z;
    }
    const double x = std::clamp(size / 2.0 + (u - cx) * scale_px, -1e6, 1e6), y = std::clamp(size / 2.0 + 14 - (v - cy) * scale_px, -1e6, 1e6);
    return cv::Point(static_cast<int>(std::lround(x)), static_cast<int>(std::lround(y)));
  };
  if (p.mesh != nullptr && !p.mesh->faces.empty()) {
    const Mesh& m = *p.mesh;
    std::vector<std::pair<double, int>> order;
    order.reserve(m.faces.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
      const Face& t = m.faces[f];
      order.emplace_back((m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]).dot(forward), static_cast<int>(f));
    }
    std::sort(order.begin(), order.end(), std::greater<>());  // far first
    const Vec3 light = (-forward + 0.4 * up + 0.3 * right).normalized();
    const bool smooth_lines = m.faces.size() <= 100000;
    for (const auto& [depth, f] : order) {
      const Face& t = m.faces[f];
      const Vec3 n = triangle_normal(m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]);
      const double shade = 0.3 + 0.7 * std::abs(n.dot(light));
      cv::Scalar c(205, 205, 205);
      if (!p.face_marked.empty() && p.face_marked[f]) c = cv::Scalar(40, 40, 230);
      else if (!p.face_values.empty() && scale) c = colour_of(p.face_values[f], *scale);
      c = cv::Scalar(c[0] * shade, c[1] * shade, c[2] * shade);
      const cv::Point pts[3] = {project(m.positions[t[0]]), project(m.positions[t[1]]), project(m.positions[t[2]])};
      cv::fillConvexPoly(img, pts, 3, c, smooth_lines ? cv::LINE_AA : cv::LINE_8);
    }
    for (const auto& [a, b] : p.edges) cv::line(img, project(m.positions[a]), project(m.positions[b]), cv::Scalar(40, 40, 40), 1, cv::LINE_AA);
  }
  if (p.points != nullptr && scale) {
    // Farthest from the mesh drawn last, so the points that matter stay visible.
    std::vector<std::size_t> order(p.points->size());
    std::iota(order.begin(), order.end(), 0);
    if (p.point_values) std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return (*p.point_values)[a] < (*p.point_values)[b]; });
    const int radius = p.points->size() > 50000 ? 1 : 2;
    for (std::size_t i : order) {
      const cv::Scalar c = p.point_values ? colour_of((*p.point_values)[i], *scale) : cv::Scalar(0, 0, 0);
      cv::circle(img, project((*p.points)[i]), radius, c, cv::FILLED);
    }
  }
  cv::putText(img, p.title, {12, 26}, kFont, 0.6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

}  // namespace

Histogram make_histogram(const std::string& name, const std::string& title, const std::string& unit, std::vector<double> values,
                         double lo, double hi, int bins) {
  Histogram h;
  h.name = name;
  h.title = title;
  h.unit = unit;
  h.lo = lo;
  h.hi = hi > lo ? hi : lo + 1.0;
  h.counts.assign(static_cast<std::size_t>(bins), 0);
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }), values.end());
  h.total = values.size();
  if (values.empty()) return h;
  std::sort(values.begin(), values.end());
  h.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  h.median = values[values.size() / 2];
  h.p95 = values[std::min(values.size() - 1, static_cast<std::size_t>(0.95 * static_cast<double>(values.size())))];
  h.max = values.back();
  for (double v : values) {
    if (v > h.hi) ++h.clipped;
    const int b = std::clamp(static_cast<int>((v - h.lo) / (h.hi - h.lo) * bins), 0, bins - 1);
    ++h.counts[static_cast<std::size_t>(b)];
  }
  return h;
}

std::vector<unsigned char> render_histogram(const Histogram& h) {
  const int W = 760, H = 470, left = 80, right = 30, top = 78, bottom = 70;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  const int pw = W - left - right, ph = H - top - bottom;
  const std::size_t peak = std::max<std::size_t>(1, *std::max_element(h.counts.begin(), h.counts.end()));
  cv::putText(img, h.title, {left, 30}, kFont, 0.6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  const double bw = static_cast<double>(pw) / static_cast<double>(h.counts.size());
  for (std::size_t b = 0; b < h.counts.size(); ++b) {
    const int bh = static_cast<int>(std::round(ph * static_cast<double>(h.counts[b]) / static_cast<double>(peak)));
    cv::rectangle(img, cv::Point(left + static_cast<int>(static_cast<double>(b) * bw) + 1, top + ph - bh),
                  cv::Point(left + static_cast<int>(static_cast<double>(b + 1) * bw) - 1, top + ph), cv::Scalar(190, 120, 40), cv::FILLED);
  }
  cv::line(img, {left, top + ph}, {left + pw, top + ph}, cv::Scalar(0, 0, 0), 1);
  cv::line(img, {left, top}, {left, top + ph}, cv::Scalar(0, 0, 0), 1);
  for (int t = 0; t <= 5; ++t) {
    const int x = left + pw * t / 5;
    cv::line(img, {x, top + ph}, {x, top + ph + 5}, cv::Scalar(0, 0, 0), 1);
    const std::string label = fmt(h.lo + (h.hi - h.lo) * t / 5.0) + (t == 5 && h.clipped ? "+" : "");
    int base = 0;
    const int tw = cv::getTextSize(label, kFont, 0.45, 1, &base).width;
    cv::putText(img, label, {std::min(x - tw / 2, W - tw - 4), top + ph + 22}, kFont, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    const int y = top + ph - ph * t / 5;
    cv::line(img, {left - 5, y}, {left, y}, cv::Scalar(0, 0, 0), 1);
    cv::putText(img, std::to_string(std::llround(static_cast<double>(peak) * t / 5.0)), {8, y + 5}, kFont, 0.42, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
  }
  int baseline = 0;
  const cv::Size unit_size = cv::getTextSize(h.unit, kFont, 0.5, 1, &baseline);
  cv::putText(img, h.unit, {left + (pw - unit_size.width) / 2, H - 18}, kFont, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, "count", {8, top - 26}, kFont, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  auto mark = [&](double v, const cv::Scalar& colour) {
    if (!(v >= h.lo && v <= h.hi)) return;
    const int x = left + static_cast<int>((v - h.lo) / (h.hi - h.lo) * pw);
    cv::line(img, {x, top}, {x, top + ph}, colour, 2);
  };
  mark(h.mean, cv::Scalar(0, 0, 220));
  mark(h.median, cv::Scalar(0, 160, 0));
  mark(h.p95, cv::Scalar(200, 0, 200));
  const std::string legend = "mean " + fmt(h.mean) + " (red)  median " + fmt(h.median) + " (green)  95% " + fmt(h.p95) +
                             " (purple)  max " + fmt(h.max) + "  n " + std::to_string(h.total);
  cv::putText(img, legend, {left, 56}, kFont, 0.38, cv::Scalar(60, 60, 60), 1, cv::LINE_AA);
  return png(img);
}

std::vector<unsigned char> render_views(const std::vector<Panel>& panels, const Camera& camera, int size,
                                        const std::optional<ColourScale>& scale) {
  const int bar = scale ? 70 : 0;
  cv::Mat img(size + bar, size * static_cast<int>(panels.size()), CV_8UC3, cv::Scalar(255, 255, 255));
  for (std::size_t k = 0; k < panels.size(); ++k) {
    cv::Mat tile = img(cv::Rect(static_cast<int>(k) * size, 0, size, size));
    render_panel(tile, panels[k], camera, scale);
    if (k > 0) cv::line(img, {static_cast<int>(k) * size, 0}, {static_cast<int>(k) * size, size}, cv::Scalar(200, 200, 200), 1);
  }
  if (scale) draw_colour_bar(img, size + 8, *scale);
  return png(img);
}

}  // namespace scanmesh::detail
