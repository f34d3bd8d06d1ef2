// A report: measure once (metrics module), choose what to show, render (figures.cpp), write the sidecar
// (sidecar.cpp) and the page (page.cpp) into the run's outputs.
#include "scanmesh/report.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "report_parts.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/errors.h"
#include "scanmesh/geometry.h"
#include "scanmesh/scan_fit.h"
#include "scanmesh/topology.h"

namespace scanmesh {

std::vector<int> framed_vertices(const Mesh& m) {
  const std::size_t nv = m.num_vertices();
  // Pieces with faces numbered 0.. (a mesh has a few; per-vertex boxes would cost 48 bytes a vertex).
  const std::vector<int> root = vertex_pieces(m);
  std::vector<int> label(nv, -1);
  std::vector<std::size_t> faces;
  for (const Face& f : m.faces) {
    int& l = label[root[f[0]]];
    if (l < 0) {
      l = static_cast<int>(faces.size());
      faces.push_back(0);
    }
    ++faces[static_cast<std::size_t>(l)];
  }
  auto piece = [&](std::size_t v) { return label[root[v]]; };  // -1: a vertex no face uses
  const Vec3 none = Vec3::Constant(std::numeric_limits<double>::infinity());
  std::vector<Vec3> lo(faces.size(), none), hi(faces.size(), -none);
  for (std::size_t v = 0; v < nv; ++v) {
    const int p = piece(v);
    if (p < 0 || !m.positions[v].allFinite()) continue;
    lo[p] = lo[p].cwiseMin(m.positions[v]);
    hi[p] = hi[p].cwiseMax(m.positions[v]);
  }
  std::vector<int> out;
  if (faces.empty()) return out;
  const auto main = static_cast<int>(std::max_element(faces.begin(), faces.end()) - faces.begin());
  const double margin = 0.25 * (hi[main] - lo[main]).norm();
  auto beside = [&](int p) {
    if (p < 0) return false;
    for (int k = 0; k < 3; ++k)
      if (lo[p][k] > hi[main][k] + margin || hi[p][k] < lo[main][k] - margin) return false;
    return true;
  };
  for (std::size_t v = 0; v < nv; ++v)
    if (m.positions[v].allFinite() && beside(piece(v))) out.push_back(static_cast<int>(v));
  return out;
}

namespace {

using detail::Camera;
using detail::ColourScale;
using detail::Panel;

double quantile(std::vector<double> v, double q) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

// From the sensor when the run knows it; else along the mean normal of a surface that mostly faces one way
// (a single view), or a three-quarter view of a closed object. Framed on the main piece and the pieces beside it.
Camera choose_camera(const Mesh& m, const FaceGeometry& g, const std::optional<Vec3>& sensor, const Vec3& sensor_up) {
  Camera cam;
  const std::vector<int> main = framed_vertices(m);
  Vec3 centre = Vec3::Zero();
  for (int v : main) centre += m.positions[v];
  centre /= static_cast<double>(std::max<std::size_t>(1, main.size()));
  Vec3 mean_normal = Vec3::Zero();
  double area = 0.0;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    mean_normal += g.areas[f] * g.normals[f];
    area += g.areas[f];
  }
  // Up: the sensor image's up when it is known, else +y (most scan and mesh formats), or +z when looking
  // along y.
  Vec3 up0 = Vec3(0, 1, 0);
  if (sensor && (centre - *sensor).norm() > 0.0) {
    cam.forward = (centre - *sensor).normalized();
    up0 = sensor_up;
  } else if (area > 0.0 && mean_normal.norm() > 0.5 * area) {
    cam.forward = -(mean_normal.normalized() + Vec3(0.15, 0.2, 0.1)).normalized();
  } else {
    cam.forward = -Vec3(0.6, 0.5, 1.0).normalized();  // front, from the right and above
  }
  if (std::abs(cam.forward.dot(up0.normalized())) > 0.95) up0 = std::abs(cam.forward.z()) < 0.95 ? Vec3(0, 0, 1) : Vec3(0, 1, 0);
  const Vec3 right = cam.forward.cross(up0).normalized();
  const Vec3 up = right.cross(cam.forward);
  cam.up = up;
  // A sensor's view is drawn in perspective from the sensor, as its image shows the scene.
  cam.perspective = sensor.has_value() && (centre - *sensor).norm() > 0.0;
  if (cam.perspective) cam.eye = *sensor;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (int v : main) {
    const Vec3& p = m.positions[v];
    double u = p.dot(right), w = p.dot(up);
    if (cam.perspective) {
      const Vec3 d = p - cam.eye;
      const double z = d.dot(cam.forward);
      if (!(z > 0.0)) continue;
      u = d.dot(right) / z;
      w = d.dot(up) / z;
    }
    x0 = std::min(x0, u);
    x1 = std::max(x1, u);
    y0 = std::min(y0, w);
    y1 = std::max(y1, w);
  }
  if (!(x1 >= x0)) x0 = x1 = y0 = y1 = 0.0;
  cam.extent = std::max({x1 - x0, y1 - y0, 1e-300});
  cam.centre_u = 0.5 * (x0 + x1);
  cam.centre_v = 0.5 * (y0 + y1);
  cam.centre = right * (0.5 * (x0 + x1)) + up * (0.5 * (y0 + y1)) + cam.forward * centre.dot(cam.forward);
  return cam;
}

std::vector<double> per_face(const Mesh& m, const std::vector<double>& per_vertex) {
  std::vector<double> out(m.num_faces());
  for (std::size_t f = 0; f < m.num_faces(); ++f)
    out[f] = (per_vertex[m.faces[f][0]] + per_vertex[m.faces[f][1]] + per_vertex[m.faces[f][2]]) / 3.0;
  return out;
}

detail::ReportContent measure_and_render(const ReportInput& in, const ReportOptions& options, const ReportPaths& paths) {
  detail::ReportContent c;
  if (in.mesh == nullptr) return c;
  const Mesh& m = *in.mesh;
  c.metrics = evaluate(m, in.reference);
  const MeshMetrics& metrics = *c.metrics;
  c.histograms.push_back(detail::make_histogram("triangle_quality", "Triangle quality Q = circumradius / shortest edge",
                                                "Q (0.577 = equilateral; lower is better)", metrics.face_quality, 0.5, 2.5, 40));
  c.histograms.push_back(detail::make_histogram("dihedral_angles", "Angle between the normals of adjacent faces (0 = flat)", "degrees",
                                                metrics.dihedral_deg, 0.0, 180.0, 36));
  std::vector<double> displacement;
  const bool moved = in.before != nullptr && in.before->num_vertices() == m.num_vertices();
  if (moved) {
    for (std::size_t v = 0; v < m.num_vertices(); ++v) displacement.push_back((m.positions[v] - in.before->positions[v]).norm());
    const double hi = std::max(quantile(displacement, 0.99), 1e-300);
    c.histograms.push_back(detail::make_histogram("vertex_displacement", "How far denoising moved each vertex", "scene units", displacement,
                                                  0.0, hi, 40));
  }
  if (metrics.same_connectivity)
    c.histograms.push_back(detail::make_histogram("normal_error", "Face normal error against the reference", "degrees",
                                                  metrics.face_angle_error, 0.0, 30.0, 30));
  if (in.scan_fit) {
    const ScanFit& f = *in.scan_fit;
    const double hi = std::max(quantile(f.point_distance, 0.99), 2.0 * f.coverage_radius);
    c.histograms.push_back(detail::make_histogram("cloud_to_mesh", "Distance from each input point to the mesh", "scene units",
                                                  f.point_distance, 0.0, hi, 40));
  }
  if (!options.figures) return c;

  FaceGeometry g;
  compute_face_geometry(m.positions, m.faces, g);
  const Camera cam = choose_camera(m, g, in.sensor, in.sensor_up);
  const int size = options.image_size;
  auto add = [&](const std::string& name, const std::string& title, const std::string& caption, std::vector<unsigned char> png) {
    c.figures.push_back({(std::filesystem::path(paths.folder) / name).string(), title, caption, std::move(png)});
  };
  // Feature edges help on CAD-like parts; on noisy scans most edges would qualify and hide the surface.
  std::vector<std::array<int, 2>> features;
  for (std::size_t e = 0; e < metrics.dihedral_deg.size(); ++e)
    if (metrics.dihedral_deg[e] > 40.0) features.push_back(metrics.manifold_edges[e]);
  const bool draw_features = features.size() < metrics.manifold_edges.size() / 20;
  Panel after;
  after.mesh = &m;
  after.title = "after";
  if (draw_features) after.edges = features;
  std::size_t flipped = 0;
  if (metrics.same_connectivity) {
    after.face_marked.assign(m.num_faces(), 0);
    for (std::size_t f = 0; f < m.num_faces(); ++f)
      if (metrics.face_angle_error[f] > 90.0) after.face_marked[f] = 1, ++flipped;
  }
  const std::string view_from = in.sensor ? "seen from the sensor" : "seen along the surface's mean normal (or from three-quarters for closed shapes)";
  const std::string edges_note = draw_features ? " Edges between faces more than 40 degrees apart are drawn dark." : "";
  const std::string flips_note = metrics.same_connectivity ? " Faces turned more than 90 degrees from the reference are red (" + std::to_string(flipped) + ")." : "";
  if (in.before != nullptr && in.before->num_faces() > 0) {
    Panel before;
    before.mesh = in.before;
    before.title = "before";
    add("view_result.png", "Before and after", "The mesh as it entered the first stage that moved its vertices (left) and the result (right), " +
                                              view_from + ", framed on the largest piece and the pieces beside it." + edges_note + flips_note,
        detail::render_views({before, after}, cam, size, std::nullopt));
  } else {
    add("view_result.png", "Result", "The mesh, " + view_from + ", framed on the largest piece and the pieces beside it." + edges_note + flips_note,
        detail::render_views({after}, cam, size, std::nullopt));
  }
  if (moved) {
    Panel p;
    p.mesh = &m;
    p.title = "vertex displacement";
    p.face_values = per_face(m, displacement);
    const ColourScale s{0.0, std::max(quantile(displacement, 0.95), 1e-300), "scene units (the scale ends at the 95th percentile)"};
    add("view_displacement.png", "How far denoising moved the surface",
        "Each face coloured by how far its vertices moved, in scene units; blue did not move, red moved " + fmt(s.hi) +
            " or more. Even colour means noise was removed evenly; a red patch shows where shape changed.",
        detail::render_views({p}, cam, size, s));
  }
  if (in.scan_fit && in.scan_points) {
    const ScanFit& f = *in.scan_fit;
    Panel p;
    p.mesh = &m;
    p.title = "input points by distance to the mesh";
    p.points = in.scan_points;
    p.point_values = &f.point_distance;
    const ColourScale s{0.0, std::max(quantile(f.point_distance, 0.95), f.coverage_radius), "scene units"};
    add("view_cloud_to_mesh.png", "Input points against the mesh",
        "Every input point coloured by its distance to the mesh, in scene units, over the mesh in grey. Red points (" + fmt(s.hi) +
            " or farther) are the ones the mesh leaves out: outliers, or surface the meshing missed.",
        detail::render_views({p}, cam, size, s));
  }
  if (metrics.same_connectivity) {
    Panel p;
    p.mesh = &m;
    p.title = "normal error";
    p.face_values = metrics.face_angle_error;
    add("view_normal_error.png", "Normal error against the reference",
        "Each face coloured by the angle between its normal and the reference face's normal; the scale ends at 20 degrees.",
        detail::render_views({p}, cam, size, ColourScale{0.0, 20.0, "degrees"}));
  }
  for (const auto& h : c.histograms)
    add("histogram_" + h.name + ".png", h.title, "Histogram; the mean (red), median (green) and 95th percentile (purple) are marked, values beyond the axis are counted in the last bar.",
        detail::render_histogram(h));
  return c;
}

}  // namespace

void write_failure_sidecar(const ReportInput& input, const std::string& error) {
  write_file_atomically(report_paths(input.output_path).json, detail::sidecar_json(input, nullptr, error));
}

std::vector<std::string> write_report(const ReportInput& in, const ReportOptions& options, OutputTransaction& outputs) {
  const ReportPaths paths = report_paths(in.output_path);
  const detail::ReportContent c = measure_and_render(in, options, paths);
  std::vector<std::string> files;
  if (options.figures) {
    std::error_code ec;
    std::filesystem::create_directories(paths.folder, ec);
    if (ec) throw OutputError("cannot create '" + paths.folder + "': " + ec.message());
    for (const auto& f : c.figures) {
      outputs.write(f.file, std::string(f.png.begin(), f.png.end()));
      files.push_back(f.file);
    }
  }
  outputs.write(paths.json, detail::sidecar_json(in, &c, ""));
  if (options.figures) outputs.write(paths.html, detail::html_page(in, c));
  return files;
}

}  // namespace scanmesh
