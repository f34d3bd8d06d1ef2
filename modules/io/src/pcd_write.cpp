// Writing PCD: binary_compressed with float fields (x y z, normals, rgb as PCL writes them), organisation
// and the sensor pose (VIEWPOINT) kept. A cloud far from the origin gets x y z as doubles (SIZE 8):
// floats would round georeferenced coordinates (UTM northings of 4e6 m) to decimetres.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>
#include <string>
#include <vector>

#include "cloud_formats.h"
#include "lzf.h"

namespace scanmesh::detail {

namespace {

// True if the cloud lies farther from the origin than 16 times its own size: a float's step there is
// over 2e-6 of the cloud's extent (PCL's own files lose that much; this writer keeps doubles instead).
bool needs_double_coordinates(const PointCloud& cloud) {
  const Box b = finite_box(cloud.points);
  if (b.empty()) return false;
  const double far = std::max(b.lo.cwiseAbs().maxCoeff(), b.hi.cwiseAbs().maxCoeff());
  return far > 16.0 * (b.hi - b.lo).norm();
}

}  // namespace

std::string encode_pcd(const PointCloud& cloud) {
  // binary_compressed with float fields: x y z, normal_x normal_y normal_z, rgb (as PCL writes them).
  std::vector<std::string> names = {"x", "y", "z"};
  if (cloud.has_normals()) names.insert(names.end(), {"normal_x", "normal_y", "normal_z"});
  if (cloud.has_colours()) names.push_back("rgb");
  const bool doubles = needs_double_coordinates(cloud);
  const std::size_t n = cloud.size();
  std::string header = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS";
  for (const auto& f : names) header += " " + f;
  header += "\nSIZE";
  for (std::size_t i = 0; i < names.size(); ++i) header += i < 3 && doubles ? " 8" : " 4";
  header += "\nTYPE";
  for (std::size_t i = 0; i < names.size(); ++i) header += " F";
  header += "\nCOUNT";
  for (std::size_t i = 0; i < names.size(); ++i) header += " 1";
  header += "\nWIDTH " + std::to_string(cloud.organized() ? cloud.width : static_cast<int>(n));
  header += "\nHEIGHT " + std::to_string(cloud.organized() ? cloud.height : 1);
  const Vec3 o = cloud.sensor_origin.value_or(Vec3::Zero());
  const Eigen::Quaterniond q(cloud.sensor_orientation);
  char vp[256];
  std::snprintf(vp, sizeof vp, "\nVIEWPOINT %.17g %.17g %.17g %.9g %.9g %.9g %.9g\n", o.x(), o.y(), o.z(), q.w(), q.x(), q.y(), q.z());
  header += vp;
  header += "POINTS " + std::to_string(n) + "\nDATA binary_compressed\n";

  std::string raw;
  raw.reserve(n * 4 * (names.size() + (doubles ? 3 : 0)));
  auto put = [&](auto v) {  // float or double, little-endian
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    if constexpr (std::endian::native != std::endian::little) std::reverse(b, b + sizeof v);
    raw.append(b, sizeof v);
  };
  for (int c = 0; c < 3; ++c)
    for (const auto& p : cloud.points) {
      if (doubles) put(p[c]);
      else put(static_cast<float>(p[c]));
    }
  if (cloud.has_normals())
    for (int c = 0; c < 3; ++c)
      for (const auto& nrm : cloud.normals) put(static_cast<float>(nrm[c]));
  if (cloud.has_colours())
    for (const auto& rgb : cloud.colours) {
      const std::uint32_t bits = (std::uint32_t{rgb[0]} << 16) | (std::uint32_t{rgb[1]} << 8) | rgb[2];
      float f;
      std::memcpy(&f, &bits, 4);
      put(f);
    }
  const std::string packed = lzf_compress(raw);
  std::string out = header;
  const auto sizes = std::array<std::uint32_t, 2>{static_cast<std::uint32_t>(packed.size()), static_cast<std::uint32_t>(raw.size())};
  for (std::uint32_t s : sizes) {
    char b[4];
    std::memcpy(b, &s, 4);
    if constexpr (std::endian::native != std::endian::little) std::swap(b[0], b[3]), std::swap(b[1], b[2]);
    out.append(b, 4);
  }
  out += packed;
  return out;
}

}  // namespace scanmesh::detail
