// PCD (PCL's point cloud format, v0.7): ascii, binary and binary_compressed bodies. Written here rather
// than taken from PCL so that every number in the header is checked against the file before anything
// is allocated, and a broken file gets a message naming what is wrong instead of a crash.
#include <array>
#include <bit>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <cstring>
#include <limits>

#include "cloud_formats.h"
#include "lzf.h"
#include "scanmesh/errors.h"

namespace scanmesh::detail {
namespace {

struct Field {
  std::string name;
  int size = 4;
  char type = 'F';
  long long count = 1;
  std::size_t offset = 0;  ///< byte offset inside one point (binary) or of its block (compressed)
};

struct Header {
  std::vector<Field> fields;
  long long width = -1, height = 1, points = -1;
  double viewpoint[7] = {0, 0, 0, 1, 0, 0, 0};
  bool has_viewpoint = false;
  std::string encoding;
  std::size_t point_size = 0;
  std::size_t body = 0;  ///< offset of the data after the DATA line
};

[[noreturn]] void fail(const std::string& file, const std::string& what) { throw InputError(file + ": " + what); }

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

bool to_int(std::string_view s, long long& v) {
  if (s.empty()) return false;
  const char* b = s.data();
  auto [p, ec] = std::from_chars(b + (s[0] == '+' ? 1 : 0), b + s.size(), v);
  return ec == std::errc() && p == b + s.size();
}

bool to_double(std::string_view s, double& v) {
  if (s.empty()) return false;
  const char* b = s.data();
  auto [p, ec] = std::from_chars(b + (s[0] == '+' ? 1 : 0), b + s.size(), v);
  if (p != b + s.size()) return false;
  if (ec == std::errc::result_out_of_range) {
    v = std::strtod(std::string(s).c_str(), nullptr);  // overflow -> inf (rejected by callers), underflow -> 0
    return true;
  }
  return ec == std::errc();
}

Header parse_header(std::string_view data, const std::string& file) {
  Header h;
  std::vector<std::string_view> names, sizes, types, counts;
  std::size_t pos = 0;
  int line_no = 0;
  bool have_data = false;
  while (pos < data.size() && !have_data) {
    std::size_t end = data.find('\n', pos);
    if (end == std::string_view::npos) end = data.size();
    const std::string_view line = data.substr(pos, end - pos);
    pos = std::min(data.size(), end + 1);
    ++line_no;
    const auto tok = split(line);
    if (tok.empty() || tok[0][0] == '#') continue;
    const std::string_view key = tok[0];
    const std::string where = "header line " + std::to_string(line_no);
    auto one_int = [&](long long& v) {
      if (tok.size() != 2 || !to_int(tok[1], v) || v < 0) fail(file, where + ": " + std::string(key) + " needs one non-negative whole number");
    };
    if (key == "VERSION") {
    } else if (key == "FIELDS" || key == "COLUMNS") {
      names.assign(tok.begin() + 1, tok.end());
    } else if (key == "SIZE") {
      sizes.assign(tok.begin() + 1, tok.end());
    } else if (key == "TYPE") {
      types.assign(tok.begin() + 1, tok.end());
    } else if (key == "COUNT") {
      counts.assign(tok.begin() + 1, tok.end());
    } else if (key == "WIDTH") {
      one_int(h.width);
    } else if (key == "HEIGHT") {
      one_int(h.height);
    } else if (key == "POINTS") {
      one_int(h.points);
    } else if (key == "VIEWPOINT") {
      if (tok.size() != 8) fail(file, where + ": VIEWPOINT needs 7 numbers (tx ty tz qw qx qy qz)");
      for (int i = 0; i < 7; ++i)
        if (!to_double(tok[i + 1], h.viewpoint[i]) || !std::isfinite(h.viewpoint[i])) fail(file, where + ": VIEWPOINT has a value that is not a finite number");
      h.has_viewpoint = true;
    } else if (key == "DATA") {
      if (tok.size() != 2) fail(file, where + ": DATA needs one of ascii, binary, binary_compressed");
      h.encoding = std::string(tok[1]);
      have_data = true;
    } else {
      fail(file, "not a PCD file: unexpected " + where + " '" + std::string(line.substr(0, 40)) + "'");
    }
  }
  if (!have_data || names.empty()) fail(file, "PCD header incomplete (needs FIELDS ... DATA); truncated or not a PCD file");
  if (h.encoding != "ascii" && h.encoding != "binary" && h.encoding != "binary_compressed")
    fail(file, "unknown PCD DATA encoding '" + h.encoding + "' (ascii, binary or binary_compressed)");
  if (sizes.size() != names.size() || types.size() != names.size() || (!counts.empty() && counts.size() != names.size()))
    fail(file, "PCD header lists " + std::to_string(names.size()) + " FIELDS but " + std::to_string(sizes.size()) + " SIZE, " +
                   std::to_string(types.size()) + " TYPE and " + std::to_string(counts.size()) + " COUNT entries");
  h.body = pos;
  // Field layout; every product is checked so a crafted header cannot overflow it.
  constexpr long long kMaxCount = 1 << 20;
  for (std::size_t i = 0; i < names.size(); ++i) {
    Field f;
    f.name = std::string(names[i]);
    long long size = 0;
    if (!to_int(sizes[i], size) || (size != 1 && size != 2 && size != 4 && size != 8))
      fail(file, "field '" + f.name + "': SIZE must be 1, 2, 4 or 8, got '" + std::string(sizes[i]) + "'");
    f.size = static_cast<int>(size);
    if (types[i].size() != 1 || (types[i][0] != 'F' && types[i][0] != 'I' && types[i][0] != 'U'))
      fail(file, "field '" + f.name + "': TYPE must be F, I or U, got '" + std::string(types[i]) + "'");
    f.type = types[i][0];
    if (f.type == 'F' && f.size != 4 && f.size != 8) fail(file, "field '" + f.name + "': a float (TYPE F) has SIZE 4 or 8");
    if (!counts.empty() && (!to_int(counts[i], f.count) || f.count < 1 || f.count > kMaxCount))
      fail(file, "field '" + f.name + "': COUNT must be a whole number in [1, " + std::to_string(kMaxCount) + "], got '" + std::string(counts[i]) + "'");
    f.offset = h.point_size;
    h.point_size += static_cast<std::size_t>(f.size) * static_cast<std::size_t>(f.count);
    if (h.point_size > (std::size_t{1} << 30)) fail(file, "PCD points of more than 1 GiB each: corrupt header");
    h.fields.push_back(std::move(f));
  }
  if (h.points < 0 && h.width >= 0 && __builtin_mul_overflow(h.width, h.height, &h.points))
    fail(file, "PCD header says WIDTH " + std::to_string(h.width) + " x HEIGHT " + std::to_string(h.height) +
                   ": more points than any file can hold");
  if (h.points < 0) fail(file, "PCD header has no POINTS (or WIDTH)");
  if (h.width < 0) h.width = h.points;
  if (h.height < 1 && h.points > 0) fail(file, "PCD HEIGHT must be at least 1");
  if (static_cast<double>(h.width) * static_cast<double>(h.height) != static_cast<double>(h.points))
    fail(file, "PCD header says WIDTH " + std::to_string(h.width) + " x HEIGHT " + std::to_string(h.height) + " but POINTS " +
                   std::to_string(h.points));
  if (h.points == 0) fail(file, "the cloud is empty (POINTS 0)");
  if (h.points > std::numeric_limits<int>::max()) fail(file, "PCD with more than 2^31 points is not supported");
  const double remaining = static_cast<double>(data.size() - h.body);
  const double need = static_cast<double>(h.points) * static_cast<double>(h.point_size);
  if (h.encoding == "binary" && need > remaining)
    fail(file, "binary PCD data is truncated: " + std::to_string(h.points) + " points of " + std::to_string(h.point_size) + " bytes need " +
                   std::to_string(static_cast<long long>(need)) + " bytes after the header, the file has " +
                   std::to_string(static_cast<long long>(remaining)));
  if (h.encoding == "ascii") {
    double values = 0.0;
    for (const auto& f : h.fields) values += static_cast<double>(f.count);
    if (static_cast<double>(h.points) * (2.0 * values - 1.0) > remaining + 1.0)
      fail(file, "ascii PCD data is truncated: " + std::to_string(h.points) + " points cannot fit in the " +
                     std::to_string(static_cast<long long>(remaining)) + " bytes after the header");
  }
  return h;
}

template <typename T>
T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

// One value of a field as double (binary bodies are little-endian, as PCL writes them).
double value_at(const Field& f, const char* p) {
  if constexpr (std::endian::native != std::endian::little) {
    char b[8];
    for (int i = 0; i < f.size; ++i) b[i] = p[f.size - 1 - i];
    p = b;
  }
  switch (f.type) {
    case 'F': return f.size == 4 ? static_cast<double>(load<float>(p)) : load<double>(p);
    case 'I':
      switch (f.size) {
        case 1: return load<std::int8_t>(p);
        case 2: return load<std::int16_t>(p);
        case 4: return load<std::int32_t>(p);
        default: return static_cast<double>(load<std::int64_t>(p));
      }
    default:
      switch (f.size) {
        case 1: return load<std::uint8_t>(p);
        case 2: return load<std::uint16_t>(p);
        case 4: return load<std::uint32_t>(p);
        default: return static_cast<double>(load<std::uint64_t>(p));
      }
  }
}

// Packed colour of a 4-byte rgb/rgba field: PCL stores 0x00RRGGBB (or 0xAARRGGBB) in the bits of a
// float or uint32.
std::uint32_t colour_bits(const char* p) {
  std::uint32_t v = 0;
  std::memcpy(&v, p, 4);
  if constexpr (std::endian::native != std::endian::little) v = ((v & 0xff) << 24) | ((v & 0xff00) << 8) | ((v >> 8) & 0xff00) | (v >> 24);
  return v;
}

int find(const Header& h, std::initializer_list<const char*> names) {
  for (std::size_t i = 0; i < h.fields.size(); ++i)
    for (const char* n : names)
      if (h.fields[i].name == n) return static_cast<int>(i);
  return -1;
}

}  // namespace

PointCloud decode_pcd(std::string_view data, const std::string& file) {
  const Header h = parse_header(data, file);
  const int fx = find(h, {"x"}), fy = find(h, {"y"}), fz = find(h, {"z"});
  if (fx < 0 || fy < 0 || fz < 0) fail(file, "the cloud has no x, y and z fields");
  const int fn[3] = {find(h, {"normal_x"}), find(h, {"normal_y"}), find(h, {"normal_z"})};
  const bool normals = fn[0] >= 0 && fn[1] >= 0 && fn[2] >= 0;
  int fc = find(h, {"rgb", "rgba"});
  if (fc >= 0 && h.fields[fc].size != 4) fc = -1;  // not a packed colour
  const auto n = static_cast<std::size_t>(h.points);

  PointCloud cloud;
  // Allocated only once the data is known to hold n points (binary and ascii: the header check; compressed:
  // after the block has expanded to its announced size).
  auto allocate = [&] {
    cloud.points.resize(n);
    if (normals) cloud.normals.resize(n);
    if (fc >= 0) cloud.colours.resize(n);
  };
  auto store_colour = [&](std::size_t i, std::uint32_t bits) {
    cloud.colours[i] = {static_cast<std::uint8_t>((bits >> 16) & 0xff), static_cast<std::uint8_t>((bits >> 8) & 0xff),
                        static_cast<std::uint8_t>(bits & 0xff)};
  };

  if (h.encoding == "ascii") {
    // One line per point, the fields' values in order; a packed float colour is read as a float and its
    // bits reinterpreted, as PCL writes it.
    std::size_t values_per_point = 0;
    std::vector<std::size_t> first(h.fields.size());
    for (std::size_t i = 0; i < h.fields.size(); ++i) {
      first[i] = values_per_point;
      values_per_point += static_cast<std::size_t>(h.fields[i].count);
    }
    std::size_t pos = h.body, point = 0, line_no = 0;
    for (std::size_t k = 0; k < h.body; ++k) line_no += data[k] == '\n' ? 1 : 0;
    std::vector<std::string_view> tok;
    allocate();
    while (pos < data.size() && point < n) {
      std::size_t end = data.find('\n', pos);
      if (end == std::string_view::npos) end = data.size();
      const std::string_view line = data.substr(pos, end - pos);
      pos = end + 1;
      ++line_no;
      tok = split(line);
      if (tok.empty()) continue;
      std::string where = file;  // "FILE:LINE: point N"
      where += ':';
      where += std::to_string(line_no);
      where += ": point ";
      where += std::to_string(point);
      if (tok.size() != values_per_point)
        fail(where, std::to_string(tok.size()) + " values, the header's fields need " + std::to_string(values_per_point));
      auto number = [&](int field) {
        double v = 0.0;
        const std::string_view t = tok[first[static_cast<std::size_t>(field)]];
        if (!to_double(t, v)) fail(where, std::string(1, '\'') + std::string(t.substr(0, 30)) + "' is not a number");
        return v;
      };
      cloud.points[point] = Vec3(number(fx), number(fy), number(fz));
      if (normals) cloud.normals[point] = Vec3(number(fn[0]), number(fn[1]), number(fn[2]));
      if (fc >= 0) {
        const double v = number(fc);
        std::uint32_t bits = 0;
        if (h.fields[fc].type == 'F') {
          const float f = static_cast<float>(v);
          std::memcpy(&bits, &f, 4);
        } else if (v >= 0.0 && v <= 4294967295.0) {
          bits = static_cast<std::uint32_t>(v);
        }
        store_colour(point, bits);
      }
      ++point;
    }
    if (point < n) fail(file, "ascii PCD data is truncated: " + std::to_string(point) + " of " + std::to_string(n) + " points");
  } else {
    std::string unpacked;
    std::string_view body;
    bool field_major = false;  // binary_compressed stores each field's values for all points together
    if (h.encoding == "binary") {
      body = data.substr(h.body, n * h.point_size);
    } else {
      if (data.size() - h.body < 8) fail(file, "binary_compressed PCD data is truncated (no block sizes)");
      const auto compressed = load<std::uint32_t>(data.data() + h.body);
      const auto uncompressed = load<std::uint32_t>(data.data() + h.body + 4);
      if (uncompressed != n * h.point_size)
        fail(file, "binary_compressed PCD block expands to " + std::to_string(uncompressed) + " bytes, but " + std::to_string(n) +
                       " points of " + std::to_string(h.point_size) + " bytes need " + std::to_string(n * h.point_size));
      if (compressed > data.size() - h.body - 8)
        fail(file, "binary_compressed PCD block of " + std::to_string(compressed) + " bytes is truncated: the file has " +
                       std::to_string(data.size() - h.body - 8) + " after the header");
      if (!lzf_decompress(data.substr(h.body + 8, compressed), uncompressed, unpacked))
        fail(file, "binary_compressed PCD block is corrupt (LZF data does not expand to the announced size)");
      body = unpacked;
      field_major = true;
    }
    allocate();
    auto at = [&](int field, std::size_t i) {
      const Field& f = h.fields[static_cast<std::size_t>(field)];
      const std::size_t element = static_cast<std::size_t>(f.size) * static_cast<std::size_t>(f.count);
      return field_major ? body.data() + n * f.offset + i * element : body.data() + i * h.point_size + f.offset;
    };
    for (std::size_t i = 0; i < n; ++i) {
      cloud.points[i] = Vec3(value_at(h.fields[fx], at(fx, i)), value_at(h.fields[fy], at(fy, i)), value_at(h.fields[fz], at(fz, i)));
      if (normals)
        cloud.normals[i] = Vec3(value_at(h.fields[fn[0]], at(fn[0], i)), value_at(h.fields[fn[1]], at(fn[1], i)),
                                value_at(h.fields[fn[2]], at(fn[2], i)));
      if (fc >= 0) store_colour(i, colour_bits(at(fc, i)));
    }
  }

  cloud.width = static_cast<int>(h.width);
  cloud.height = static_cast<int>(h.height);
  if (cloud.height <= 1) {
    cloud.width = static_cast<int>(n);
    cloud.height = 1;
  }
  // VIEWPOINT defaults to the origin. For organized frames (depth cameras) that is where the sensor is;
  // for unorganized clouds it usually only means "unknown", so it is not used there.
  const Vec3 origin(h.viewpoint[0], h.viewpoint[1], h.viewpoint[2]);
  if (origin.norm() > 0.0) cloud.sensor_origin = origin;
  else if (cloud.height > 1) cloud.sensor_origin = Vec3::Zero();
  else cloud.normals_oriented = false;
  const Eigen::Quaterniond q(h.viewpoint[3], h.viewpoint[4], h.viewpoint[5], h.viewpoint[6]);
  if (q.norm() > 0.0) cloud.sensor_orientation = q.normalized().toRotationMatrix();
  return cloud;
}

}  // namespace scanmesh::detail
