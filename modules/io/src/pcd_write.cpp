// Writing PCD: binary_compressed with float fields (x y z, normals, rgb as PCL writes them), organisation
// and the sensor pose (VIEWPOINT) kept.
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

std::string encode_pcd(const PointCloud& cloud) {
  // binary_compressed with float fields: x y z, normal_x normal_y normal_z, rgb (as PCL writes them).
  std::vector<std::string> names = {"x", "y", "z"};
  if (cloud.has_normals()) names.insert(names.end(), {"normal_x", "normal_y", "normal_z"});
  if (cloud.has_colours()) names.push_back("rgb");
  const std::size_t n = cloud.size();
  std::string header = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS";
  for (const auto& f : names) header += " " + f;
  header += "\nSIZE";
  for (std::size_t i = 0; i < names.size(); ++i) header += " 4";
  header += "\nTYPE";
  for (std::size_t i = 0; i < names.size(); ++i) header += " F";
  header += "\nCOUNT";
  for (std::size_t i = 0; i < names.size(); ++i) header += " 1";
  header += "\nWIDTH " + std::to_string(cloud.organized() ? cloud.width : static_cast<int>(n));
  header += "\nHEIGHT " + std::to_string(cloud.organized() ? cloud.height : 1);
  const Vec3 o = cloud.sensor_origin.value_or(Vec3::Zero());
  const Eigen::Quaterniond q(cloud.sensor_orientation);
  char vp[256];
  std::snprintf(vp, sizeof vp, "\nVIEWPOINT %.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", o.x(), o.y(), o.z(), q.w(), q.x(), q.y(), q.z());
  header += vp;
  header += "POINTS " + std::to_string(n) + "\nDATA binary_compressed\n";

  std::string raw;
  raw.reserve(n * 4 * names.size());
  auto put = [&](float v) {
    char b[4];
    std::memcpy(b, &v, 4);
    if constexpr (std::endian::native != std::endian::little) std::swap(b[0], b[3]), std::swap(b[1], b[2]);
    raw.append(b, 4);
  };
  for (int c = 0; c < 3; ++c)
    for (const auto& p : cloud.points) put(static_cast<float>(p[c]));
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
