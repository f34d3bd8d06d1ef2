// Cloud readers. PCD and PLY decoding is PCL's (pcl::io); this file adds what PCL does not: header
// checks with clear messages (PCL logs and returns -1), Stanford .conf poses, and XYZ text.
#include "scanmesh/cloud_io.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/common/io.h>
#include <pcl/console/print.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scanmesh/atomic_file.h"
#include "scanmesh/errors.h"
#include "scanmesh/mesh_io.h"

namespace scanmesh {
namespace {

bool has_field(const pcl::PCLPointCloud2& c, const std::string& name) {
  for (const auto& f : c.fields)
    if (f.name == name) return true;
  return false;
}

// Copies positions, normals and colours out of a PCL blob; NaN points stay (callers decide).
PointCloud from_blob(const pcl::PCLPointCloud2& blob, const std::string& path, const Eigen::Vector4f& o,
                     const Eigen::Quaternionf& q) {
  if (!has_field(blob, "x") || !has_field(blob, "y") || !has_field(blob, "z"))
    throw InputError(path + ": the cloud has no x, y and z fields");
  PointCloud out;
  pcl::PointCloud<pcl::PointXYZ> xyz;
  pcl::fromPCLPointCloud2(blob, xyz);
  out.points.reserve(xyz.size());
  for (const auto& p : xyz.points) out.points.emplace_back(p.x, p.y, p.z);
  out.width = static_cast<int>(xyz.width);
  out.height = static_cast<int>(std::max<std::uint32_t>(1, xyz.height));
  if (static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height) != out.points.size()) {
    out.width = static_cast<int>(out.points.size());
    out.height = 1;
  }
  if (has_field(blob, "normal_x") && has_field(blob, "normal_y") && has_field(blob, "normal_z")) {
    pcl::PointCloud<pcl::Normal> n;
    pcl::fromPCLPointCloud2(blob, n);
    out.normals.reserve(n.size());
    for (const auto& q : n.points) out.normals.emplace_back(q.normal_x, q.normal_y, q.normal_z);
  }
  if (has_field(blob, "rgb") || has_field(blob, "rgba")) {
    pcl::PointCloud<pcl::PointXYZRGB> c;
    pcl::fromPCLPointCloud2(blob, c);
    out.colours.reserve(c.size());
    for (const auto& q : c.points) out.colours.push_back({q.r, q.g, q.b});
  }
  // PCD's VIEWPOINT defaults to the origin. For organized frames (depth cameras) that is where the sensor
  // is; for unorganized clouds it usually only means "unknown", so it is not used there.
  if (o.head<3>().allFinite() && o.head<3>().norm() > 0.0f) out.sensor_origin = o.head<3>().cast<double>();
  else if (out.height > 1) out.sensor_origin = Vec3::Zero();
  else out.normals_oriented = false;
  out.sensor_orientation = q.toRotationMatrix().cast<double>();
  return out;
}

// Checks a PCD header so that broken files get a message naming the problem instead of PCL's log line.
void check_pcd_header(const std::string& path, const std::string& data) {
  std::istringstream in(data);
  std::string line;
  long long points = -1, width = -1, height = -1;
  std::vector<int> sizes, counts;
  std::string encoding;
  std::size_t header_bytes = 0;
  bool have_fields = false;
  while (std::getline(in, line)) {
    header_bytes += line.size() + 1;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream l(line);
    std::string key;
    l >> key;
    if (key == "FIELDS") have_fields = true;
    else if (key == "SIZE") for (int s; l >> s;) sizes.push_back(s);
    else if (key == "COUNT") for (int c; l >> c;) counts.push_back(c);
    else if (key == "WIDTH") l >> width;
    else if (key == "HEIGHT") l >> height;
    else if (key == "POINTS") l >> points;
    else if (key == "DATA") {
      l >> encoding;
      break;
    } else if (key != "VERSION" && key != "TYPE" && key != "VIEWPOINT") {
      throw InputError(path + ": not a PCD file: unexpected header line '" + line.substr(0, 40) + "'");
    }
  }
  if (!have_fields || encoding.empty())
    throw InputError(path + ": PCD header incomplete (needs FIELDS ... DATA); truncated or not a PCD file");
  if (encoding != "ascii" && encoding != "binary" && encoding != "binary_compressed")
    throw InputError(path + ": unknown PCD DATA encoding '" + encoding + "'");
  if (points < 0) points = (width >= 0 && height >= 0) ? width * height : -1;
  if (points < 0) throw InputError(path + ": PCD header has no POINTS (or WIDTH/HEIGHT)");
  if (points == 0) throw InputError(path + ": the cloud is empty (POINTS 0)");
  if (encoding == "binary") {
    long long point_bytes = 0;
    for (std::size_t i = 0; i < sizes.size(); ++i) point_bytes += sizes[i] * (i < counts.size() ? counts[i] : 1);
    const long long need = static_cast<long long>(header_bytes) + points * point_bytes;
    if (static_cast<long long>(data.size()) < need)
      throw InputError(path + ": binary PCD data is truncated: " + std::to_string(points) + " points need " +
                       std::to_string(need) + " bytes, the file has " + std::to_string(data.size()));
  }
  if (encoding == "binary_compressed" && data.size() < header_bytes + 8)
    throw InputError(path + ": binary_compressed PCD data is truncated");
}

// Stanford .conf: "bmesh FILE tx ty tz qx qy qz qw". Returns true and the pose if `file` is listed.
bool find_conf_pose(const std::filesystem::path& scan, Eigen::Isometry3d& pose, std::string& conf_name) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(scan.parent_path().empty() ? "." : scan.parent_path(), ec)) {
    if (e.path().extension() != ".conf") continue;
    std::ifstream in(e.path());
    std::string line;
    while (std::getline(in, line)) {
      std::istringstream l(line);
      std::string key, name;
      double t[3], q[4];
      if (!(l >> key >> name) || key != "bmesh" || name != scan.filename().string()) continue;
      if (!(l >> t[0] >> t[1] >> t[2] >> q[0] >> q[1] >> q[2] >> q[3])) continue;
      pose = Eigen::Isometry3d::Identity();
      pose.linear() = Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized().toRotationMatrix();
      pose.translation() = Vec3(t[0], t[1], t[2]);
      conf_name = e.path().filename().string();
      return true;
    }
  }
  return false;
}

PointCloud read_ply_cloud(const std::string& path, const std::string& data, std::vector<std::string>& warnings) {
  if (data.rfind("ply", 0) != 0) throw InputError(path + ": not a PLY file: the first line must be 'ply'");
  const auto end = data.find("end_header");
  if (end == std::string::npos) throw InputError(path + ": PLY header has no 'end_header' line (truncated?)");
  const std::string header = data.substr(0, end);
  if (header.find("element vertex") == std::string::npos) throw InputError(path + ": PLY file has no vertex element");
  const bool range_grid = header.find("element range_grid") != std::string::npos;
  if (!range_grid) {
    // Plain PLY point clouds (any scalar types, e.g. double) through scanmesh's own PLY reader.
    const Mesh m = decode_ply_points(data, path, &warnings);  // the bytes read_cloud already holds
    PointCloud cloud;
    cloud.points = m.positions;
    cloud.width = static_cast<int>(m.positions.size());
    const VertexProperty* n[3] = {m.find_property("nx"), m.find_property("ny"), m.find_property("nz")};
    if (n[0] && n[1] && n[2])
      for (std::size_t i = 0; i < m.positions.size(); ++i) cloud.normals.emplace_back(n[0]->values[i], n[1]->values[i], n[2]->values[i]);
    const VertexProperty* c[3] = {m.find_property("red"), m.find_property("green"), m.find_property("blue")};
    if (c[0] && c[1] && c[2])
      for (std::size_t i = 0; i < m.positions.size(); ++i)
        cloud.colours.push_back({static_cast<std::uint8_t>(c[0]->values[i]), static_cast<std::uint8_t>(c[1]->values[i]),
                                 static_cast<std::uint8_t>(c[2]->values[i])});
    return cloud;
  }
  // Stanford range grids (organized, float) through PCL's PLY reader, which understands `range_grid`.
  pcl::PCLPointCloud2 blob;
  pcl::PLYReader reader;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version = 0;
  if (reader.read(path, blob, origin, orientation, version, 0) < 0 || blob.data.empty())
    throw InputError(path + ": PLY data could not be read (truncated or malformed body)");
  PointCloud cloud = from_blob(blob, path, origin, orientation);
  cloud.sensor_origin.reset();
  if (range_grid) {
    Eigen::Isometry3d pose;
    std::string conf;
    if (find_conf_pose(path, pose, conf)) {
      for (auto& p : cloud.points)
        if (p.allFinite()) p = pose * p;
      for (auto& n : cloud.normals) n = pose.linear() * n;
      // The range scanner looked at the object from the scan frame's +z side.
      cloud.sensor_origin = pose * Vec3(0.0, 0.0, 1.0);
    } else {
      warnings.push_back(path + ": range scan without a .conf pose beside it; used as it is");
    }
  }
  return cloud;
}

PointCloud read_xyz(const std::string& path, const std::string& data) {
  PointCloud cloud;
  std::istringstream in(data);
  std::string line;
  std::size_t line_no = 0;
  int columns = -1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#' || line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream l(line);
    std::vector<double> v;
    std::string tok;
    while (l >> tok) {
      try {
        std::size_t used = 0;
        v.push_back(std::stod(tok, &used));
        if (used != tok.size()) throw std::invalid_argument(tok);
      } catch (const std::exception&) {
        if (tok == "nan" || tok == "NaN") v.push_back(std::nan(""));
        else throw InputError(path + ":" + std::to_string(line_no) + ": '" + tok + "' is not a number");
      }
    }
    if (v.size() != 3 && v.size() != 6)
      throw InputError(path + ":" + std::to_string(line_no) + ": expected 3 (x y z) or 6 (x y z nx ny nz) columns, found " +
                       std::to_string(v.size()));
    if (columns < 0) columns = static_cast<int>(v.size());
    if (static_cast<int>(v.size()) != columns)
      throw InputError(path + ":" + std::to_string(line_no) + ": " + std::to_string(v.size()) + " columns, but earlier lines have " +
                       std::to_string(columns));
    cloud.points.emplace_back(v[0], v[1], v[2]);
    if (columns == 6) cloud.normals.emplace_back(v[3], v[4], v[5]);
  }
  cloud.width = static_cast<int>(cloud.points.size());
  return cloud;
}

}  // namespace

bool is_cloud_extension(const std::string& ext) {
  return ext == ".pcd" || ext == ".ply" || ext == ".xyz" || ext == ".txt" || ext == ".pts";
}

PointCloud read_cloud(const std::string& path, std::vector<std::string>* warnings) {
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);  // errors are reported by exceptions instead
  std::vector<std::string> local;
  std::vector<std::string>& w = warnings != nullptr ? *warnings : local;
  const std::string ext = lower_extension(path);
  if (!is_cloud_extension(ext))
    throw InputError("'" + path + "': unknown point-cloud format '" + (ext.empty() ? std::string("(no extension)") : ext) +
                     "'; supported: .pcd .ply .xyz .txt .pts");
  const std::string data = read_file(path);
  if (data.empty()) throw InputError("'" + path + "': file is empty");
  PointCloud cloud;
  if (ext == ".pcd") {
    check_pcd_header(path, data);
    pcl::PCLPointCloud2 blob;
    Eigen::Vector4f origin;
    Eigen::Quaternionf orientation;
    if (pcl::io::loadPCDFile(path, blob, origin, orientation) < 0 || blob.data.empty())
      throw InputError(path + ": PCD data could not be decoded (truncated or corrupt)");
    cloud = from_blob(blob, path, origin, orientation);
  } else if (ext == ".ply") {
    cloud = read_ply_cloud(path, data, w);
  } else {
    cloud = read_xyz(path, data);
  }
  if (!cloud.organized()) drop_non_finite(cloud);
  if (cloud.finite_count() == 0) throw InputError(path + ": the cloud has no point with finite coordinates");
  return cloud;
}

void write_cloud_ply(const PointCloud& cloud, const std::string& path) {
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
  write_mesh(m, path);
}

void write_cloud_pcd(const PointCloud& cloud, const std::string& path) {
  namespace fs = std::filesystem;
  pcl::PointCloud<pcl::PointXYZ> pc;
  pc.width = static_cast<std::uint32_t>(cloud.width);
  pc.height = static_cast<std::uint32_t>(cloud.height);
  pc.is_dense = false;
  pc.points.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i)
    pc.points[i] = pcl::PointXYZ(static_cast<float>(cloud.points[i].x()), static_cast<float>(cloud.points[i].y()),
                                 static_cast<float>(cloud.points[i].z()));
  if (cloud.sensor_origin) {
    pc.sensor_origin_ = Eigen::Vector4f(static_cast<float>(cloud.sensor_origin->x()), static_cast<float>(cloud.sensor_origin->y()),
                                        static_cast<float>(cloud.sensor_origin->z()), 0.0f);
    pc.sensor_orientation_ = Eigen::Quaternionf(cloud.sensor_orientation.cast<float>());
  }
  const fs::path target(path);
  const fs::path tmp = (target.has_parent_path() ? target.parent_path() : fs::path(".")) / ("." + target.filename().string() + ".tmp");
  if (pcl::io::savePCDFileBinaryCompressed(tmp.string(), pc) < 0) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw OutputError("cannot write '" + path + "'");
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) throw OutputError("cannot write '" + path + "': " + ec.message());
}

}  // namespace scanmesh
