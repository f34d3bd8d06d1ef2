// Cloud readers: format dispatch, PLY clouds and range grids (through the io module's PLY reader),
// Stanford .conf poses, and the checks every cloud passes before the stages see it.
#include "scanmesh/cloud_io.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "cloud_formats.h"
#include "formats.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/errors.h"
#include "scanmesh/mesh_io.h"

namespace scanmesh {
namespace {

// Beyond this the cloud stages (PCL, single precision) cannot square distances.
constexpr double kMaxCoordinate = 1e18;

// The cloud of a PLY file read as a mesh's vertices (`grid`: its range grid, if it has one). An
// unorganized cloud takes the mesh's positions over, so the points are not held twice.
PointCloud ply_cloud(Mesh m, const RangeGrid& grid) {
  PointCloud cloud;
  const VertexProperty* n[3] = {m.find_property("nx"), m.find_property("ny"), m.find_property("nz")};
  const VertexProperty* c[3] = {m.find_property("red"), m.find_property("green"), m.find_property("blue")};
  const bool normals = n[0] && n[1] && n[2], colours = c[0] && c[1] && c[2];
  auto normal = [&](std::size_t i) { return Vec3(n[0]->values[i], n[1]->values[i], n[2]->values[i]); };
  auto colour = [&](std::size_t i) {
    return std::array<std::uint8_t, 3>{static_cast<std::uint8_t>(std::clamp(c[0]->values[i], 0.0, 255.0)),
                                       static_cast<std::uint8_t>(std::clamp(c[1]->values[i], 0.0, 255.0)),
                                       static_cast<std::uint8_t>(std::clamp(c[2]->values[i], 0.0, 255.0))};
  };
  if (grid.cols == 0) {
    const std::size_t count = m.positions.size();
    cloud.points = std::move(m.positions);
    if (normals) cloud.normals.reserve(count);
    if (colours) cloud.colours.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
      if (normals) cloud.normals.push_back(normal(i));
      if (colours) cloud.colours.push_back(colour(i));
    }
    cloud.width = static_cast<int>(cloud.points.size());
    return cloud;
  }
  auto add = [&](std::size_t i) {
    cloud.points.push_back(m.positions[i]);
    if (normals) cloud.normals.push_back(normal(i));
    if (colours) cloud.colours.push_back(colour(i));
  };
  // A range image: one point per grid cell, NaN where the scanner saw nothing.
  const double nan = std::nan("");
  for (int cell : grid.cells) {
    if (cell >= 0) {
      add(static_cast<std::size_t>(cell));
    } else {
      cloud.points.push_back(Vec3::Constant(nan));
      if (normals) cloud.normals.push_back(Vec3::Constant(nan));
      if (colours) cloud.colours.push_back({0, 0, 0});
    }
  }
  cloud.width = grid.cols;
  cloud.height = grid.rows;
  if (cloud.height <= 1) {
    cloud.width = static_cast<int>(cloud.points.size());
    cloud.height = 1;
  }
  return cloud;
}

PointCloud ply_cloud(std::string_view data, const std::string& file, std::vector<std::string>& warnings) {
  RangeGrid grid;
  Mesh m = decode_ply_points(data, file, &warnings, &grid);
  return ply_cloud(std::move(m), grid);
}

// Every coordinate finite (NaN = no measurement) and within what the stages can process.
void check_points(PointCloud& cloud, const std::string& file) {
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& p = cloud.points[i];
    if (p.hasNaN()) continue;
    if (!p.allFinite()) throw InputError(file + ": point " + std::to_string(i) + " has an infinite coordinate");
    if (p.cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw InputError(file + ": point " + std::to_string(i) + " has a coordinate beyond +-1e18, more than the cloud stages can process");
  }
  if (cloud.has_normals())
    for (auto& n : cloud.normals)
      if (!n.allFinite()) n = Vec3::Constant(std::nan(""));
  if (!cloud.organized()) drop_non_finite(cloud);
  if (cloud.finite_count() == 0) throw InputError(file + ": the cloud has no point with finite coordinates");
}

}  // namespace

bool is_cloud_extension(const std::string& ext) {
  return ext == ".pcd" || ext == ".ply" || ext == ".xyz" || ext == ".txt" || ext == ".csv" || ext == ".pts";
}

bool holds_cloud(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".ply") return is_cloud_extension(ext);
  const std::string head = read_file_head(path, 4096);
  for (const char* element : {"element face ", "element tristrips "}) {
    const std::size_t at = head.find(element);
    if (at != std::string::npos && head.compare(at + std::strlen(element), 2, "0\n") != 0 &&
        head.compare(at + std::strlen(element), 3, "0\r\n") != 0)
      return false;
  }
  return true;
}

PointCloud decode_cloud(std::string_view data, const std::string& file, std::vector<std::string>* warnings,
                        const CloudReadOptions& options) {
  std::vector<std::string> local;
  std::vector<std::string>& w = warnings != nullptr ? *warnings : local;
  const std::string ext = lower_extension(file);
  if (data.empty()) throw InputError(file + ": file is empty");
  PointCloud cloud;
  if (ext == ".pcd") cloud = detail::decode_pcd(data, file);
  else if (ext == ".ply") cloud = ply_cloud(data, file, w);
  else if (ext == ".xyz" || ext == ".txt" || ext == ".csv" || ext == ".pts") cloud = detail::decode_xyz(data, file, options.columns, w);
  else throw InputError(file + ": unknown point-cloud format '" + ext + "'");
  check_points(cloud, file);
  return cloud;
}

bool parse_conf_pose(std::string_view conf_text, const std::string& conf_file, const std::string& scan_name,
                     Eigen::Isometry3d& pose) {
  std::istringstream in{std::string(conf_text)};
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream l(line);
    std::string key, name;
    if (!(l >> key >> name) || key != "bmesh" || name != scan_name) continue;
    double v[7];
    for (double& x : v)
      if (!(l >> x) || !std::isfinite(x))
        throw InputError(conf_file + ":" + std::to_string(line_no) + ": 'bmesh " + name + "' needs 7 finite numbers (tx ty tz qx qy qz qw)");
    const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (!(q.norm() > 1e-9)) throw InputError(conf_file + ":" + std::to_string(line_no) + ": the rotation quaternion is zero");
    // Scanalyze's convention: the quaternion's conjugate rotates scan coordinates into the common frame
    // (measured: the three bunny scans overlap to a median 0.3 mm this way, 29 mm with the quaternion as it is).
    pose = Eigen::Isometry3d::Identity();
    pose.linear() = q.normalized().conjugate().toRotationMatrix();
    pose.translation() = Vec3(v[0], v[1], v[2]);
    return true;
  }
  return false;
}

PointCloud read_cloud(const std::string& path, std::vector<std::string>* warnings, const CloudReadOptions& options) {
  namespace fs = std::filesystem;
  std::vector<std::string> local;
  std::vector<std::string>& w = warnings != nullptr ? *warnings : local;
  std::error_code ec;
  if (fs::is_directory(path, ec))
    throw InputError("'" + path + "' is a folder; give one cloud file (several views go into one mesh with a pipeline's cloud.merge stage)");
  const std::string ext = lower_extension(path);
  if (ext == ".las" || ext == ".laz" || ext == ".e57")
    throw InputError("'" + path + "': " + ext + " is not supported (Debian has no library for it); convert it first, e.g. with PDAL: "
                     "pdal translate '" + path + "' cloud.ply (or CloudCompare: File > Save as PLY)");
  if (!is_cloud_extension(ext))
    throw InputError("'" + path + "': unknown point-cloud format '" + (ext.empty() ? std::string("(no extension)") : ext) +
                     "'; supported: .pcd .ply .xyz .txt .csv .pts");
  PointCloud cloud;
  if (ext == ".ply" && fs::is_regular_file(path, ec) && fs::file_size(path, ec) > detail::kWholeFileLimit && !ec) {
    // A big PLY cloud's body is read a chunk at a time rather than held whole next to the points.
    RangeGrid grid;
    Mesh m = detail::read_ply_file(path, w, false, &grid);
    if (m.positions.empty()) throw InputError("'" + path + "': contains no vertices");
    cloud = ply_cloud(std::move(m), grid);
    check_points(cloud, path);
  } else {
    cloud = decode_cloud(read_file(path), path, &w, options);
  }
  if (ext == ".ply" && cloud.organized()) {
    // A Stanford range scan: its pose is in a .conf beside it.
    const fs::path scan(path);
    Eigen::Isometry3d pose;
    bool found = false;
    for (const auto& e : fs::directory_iterator(scan.parent_path().empty() ? "." : scan.parent_path(), ec)) {
      if (e.path().extension() != ".conf") continue;
      std::string text;
      try {
        text = read_file(e.path().string());
      } catch (const InputError&) {
        continue;
      }
      if ((found = parse_conf_pose(text, e.path().string(), scan.filename().string(), pose))) break;
    }
    if (found) {
      for (auto& p : cloud.points)
        if (p.allFinite()) p = pose * p;
      for (auto& n : cloud.normals) n = pose.linear() * n;
      // The range scanner looked at the object from the scan frame's +z side.
      cloud.sensor_origin = pose * Vec3(0.0, 0.0, 1.0);
    } else {
      w.push_back(path + ": range scan without a .conf pose beside it; used as it is");
    }
  }
  return cloud;
}

namespace {

Mesh cloud_as_mesh(const PointCloud& cloud) {
  Mesh m;
  m.positions = cloud.points;
  if (cloud.has_normals()) {
    const char* names[3] = {"nx", "ny", "nz"};
    for (int c = 0; c < 3; ++c) {
      VertexProperty p{names[c], ScalarType::float32, {}};
      for (const auto& n : cloud.normals) p.values.push_back(n[c]);
      m.vertex_properties.push_back(std::move(p));
    }
  }
  if (cloud.has_colours()) {
    const char* names[3] = {"red", "green", "blue"};
    for (int c = 0; c < 3; ++c) {
      VertexProperty p{names[c], ScalarType::uint8, {}};
      for (const auto& rgb : cloud.colours) p.values.push_back(rgb[c]);
      m.vertex_properties.push_back(std::move(p));
    }
  }
  return m;
}

}  // namespace

void encode_cloud(const PointCloud& cloud, const std::string& extension, const ByteSink& sink) {
  if (extension == ".pcd") return sink(detail::encode_pcd(cloud));
  if (extension == ".ply") return encode_mesh(cloud_as_mesh(cloud), ".ply", {}, sink);
  throw UsageError("cannot write a point cloud as '" + extension + "'; use .ply or .pcd");
}

std::string encode_cloud(const PointCloud& cloud, const std::string& extension) {
  std::string out;
  encode_cloud(cloud, extension, [&out](std::string_view piece) { out += piece; });
  return out;
}

void write_cloud_ply(const PointCloud& cloud, const std::string& path) {
  write_file_atomically(path, [&](const ByteSink& sink) { encode_cloud(cloud, ".ply", sink); });
}

void write_cloud_pcd(const PointCloud& cloud, const std::string& path) {
  write_file_atomically(path, [&](const ByteSink& sink) { encode_cloud(cloud, ".pcd", sink); });
}

}  // namespace scanmesh
