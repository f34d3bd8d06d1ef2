// Text point clouds (.xyz .txt .csv .pts): one point per line, values separated by blanks, commas or
// semicolons, an optional header line naming the columns, '#' or '//' comments, and the point count that
// .pts files put on their first line. What each column holds comes from --columns, else from the header,
// else from the data: three columns are a position; four add an intensity; in six, the last three are
// normals only if they have unit length and colours only if they are whole numbers 0-255 (or fractions
// in [0, 1]); anything else asks for --columns instead of guessing.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include "cloud_formats.h"
#include "scanmesh/errors.h"

namespace scanmesh::detail {
namespace {

// A column's role: x y z, normal nx ny nz, colour r g b, or ignored (intensity, anything else).
enum class Role { x, y, z, nx, ny, nz, r, g, b, skip };

bool role_of(std::string name, Role& role) {
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  if (name == "x") role = Role::x;
  else if (name == "y") role = Role::y;
  else if (name == "z") role = Role::z;
  else if (name == "nx" || name == "normal_x" || name == "normalx") role = Role::nx;
  else if (name == "ny" || name == "normal_y" || name == "normaly") role = Role::ny;
  else if (name == "nz" || name == "normal_z" || name == "normalz") role = Role::nz;
  else if (name == "r" || name == "red") role = Role::r;
  else if (name == "g" || name == "green") role = Role::g;
  else if (name == "b" || name == "blue") role = Role::b;
  else if (name == "i" || name == "intensity" || name == "_" || name == "skip") role = Role::skip;
  else return false;
  return true;
}

std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  auto sep = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == ',' || c == ';'; };
  while (i < line.size()) {
    while (i < line.size() && sep(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !sep(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// Parses a number; "nan" is allowed (an invalid point); an overflowing value is not.
enum class Parsed { ok, not_a_number, too_large };
Parsed number(std::string_view t, double& v) {
  const char* b = t.data() + (!t.empty() && t[0] == '+' ? 1 : 0);
  const char* e = t.data() + t.size();
  auto [p, ec] = std::from_chars(b, e, v);
  if (p != e || t.empty()) return Parsed::not_a_number;
  if (ec == std::errc::result_out_of_range) {
    v = std::strtod(std::string(t).c_str(), nullptr);
    return std::isinf(v) ? Parsed::too_large : Parsed::ok;
  }
  if (ec != std::errc()) return Parsed::not_a_number;
  return std::isinf(v) ? Parsed::too_large : Parsed::ok;
}

std::string role_list(const std::vector<Role>& roles) {
  static const char* names[] = {"x", "y", "z", "nx", "ny", "nz", "r", "g", "b", "_"};
  std::string s;
  for (std::size_t i = 0; i < roles.size(); ++i) {
    if (i > 0) s += ',';
    s += names[static_cast<int>(roles[i])];
  }
  return s;
}

std::vector<Role> parse_roles(const std::string& spec, const std::string& file) {
  std::vector<Role> roles;
  for (std::string_view f : fields(spec)) {
    Role r;
    if (!role_of(std::string(f), r))
      throw UsageError(file + ": --columns: unknown column '" + std::string(f) + "'; use x y z nx ny nz r g b i (intensity) or _ (skip)");
    roles.push_back(r);
  }
  return roles;
}

}  // namespace

PointCloud decode_xyz(std::string_view data, const std::string& file, const std::string& columns,
                      std::vector<std::string>& warnings) {
  struct Line {
    std::size_t number;
    std::vector<std::string_view> values;
  };
  // Pass 1 finds the header (or .pts count line) and keeps the first 10,000 data lines to sniff the
  // columns from; pass 2 reads every point. Both walk the lines the same way.
  std::vector<std::string_view> header;
  std::size_t header_line = 0, count_line = 0;
  long long announced = -1;
  auto walk = [&](bool first_pass, const auto& on_data) {
    std::size_t pos = 0, line_no = 0;
    bool any_data = false;
    while (pos < data.size()) {
      std::size_t end = data.find('\n', pos);
      if (end == std::string_view::npos) end = data.size();
      std::string_view line = data.substr(pos, end - pos);
      pos = end + 1;
      ++line_no;
      const std::size_t first = line.find_first_not_of(" \t\r");
      if (first == std::string_view::npos) continue;
      line.remove_prefix(first);
      const bool slash_comment = line.size() >= 2 && line[0] == '/' && line[1] == '/';
      if (line[0] == '#' || slash_comment) {
        // CloudCompare writes its column names as "//X,Y,Z,R,G,B".
        if (first_pass && !any_data && header.empty() && slash_comment) {
          auto h = fields(line.substr(2));
          Role r;
          if (!h.empty() && std::all_of(h.begin(), h.end(), [&](std::string_view t) { return role_of(std::string(t), r); })) {
            header = h;
            header_line = line_no;
          }
        }
        continue;
      }
      if (line_no == header_line || line_no == count_line) continue;
      auto values = fields(line);
      if (first_pass && !any_data && header.empty()) {
        double v;
        if (std::all_of(values.begin(), values.end(), [&](std::string_view t) { return number(t, v) == Parsed::not_a_number; })) {
          header = values;  // the first line names the columns
          header_line = line_no;
          continue;
        }
      }
      if (first_pass && !any_data && count_line == 0 && values.size() == 1) {
        long long n = 0;
        auto [p, ec] = std::from_chars(values[0].data(), values[0].data() + values[0].size(), n);
        if (ec == std::errc() && p == values[0].data() + values[0].size() && n >= 0) {
          announced = n;  // .pts: the point count on the first line
          count_line = line_no;
          continue;
        }
      }
      any_data = true;
      if (!on_data(line_no, values)) return;
    }
  };
  std::vector<Line> lines;
  walk(true, [&](std::size_t line_no, std::vector<std::string_view>& values) {
    lines.push_back({line_no, std::move(values)});
    return lines.size() < 10000;
  });
  if (lines.empty()) throw InputError(file + ": no points (no line of numbers)");
  const std::size_t ncols = lines.front().values.size();

  std::vector<Role> roles;
  if (!columns.empty()) {
    roles = parse_roles(columns, file);
  } else if (!header.empty()) {
    for (std::string_view name : header) {
      Role r = Role::skip;
      if (!role_of(std::string(name), r))
        warnings.push_back(file + ":" + std::to_string(header_line) + ": column '" + std::string(name) + "' is not used");
      roles.push_back(r);
    }
  } else {
    // Sniff from up to 10,000 lines what columns 4-6 (and 5-7) hold.
    const std::size_t probe = std::min<std::size_t>(lines.size(), 10000);
    auto looks_like_colour = [&](std::size_t c0) {
      bool bytes = true, unit = true;
      for (std::size_t i = 0; i < probe && (bytes || unit); ++i) {
        if (lines[i].values.size() < c0 + 3) return false;
        for (std::size_t c = c0; c < c0 + 3; ++c) {
          double v = 0;
          if (number(lines[i].values[c], v) != Parsed::ok) return false;
          bytes = bytes && v >= 0 && v <= 255 && v == std::floor(v);
          unit = unit && v >= 0 && v <= 1;
        }
      }
      return bytes || unit;
    };
    auto looks_like_normal = [&](std::size_t c0) {
      std::size_t unit = 0;
      for (std::size_t i = 0; i < probe; ++i) {
        if (lines[i].values.size() < c0 + 3) return false;
        double n[3];
        for (int c = 0; c < 3; ++c)
          if (number(lines[i].values[c0 + c], n[c]) != Parsed::ok) return false;
        unit += std::abs(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1.0) < 0.02 ? 1 : 0;
      }
      return unit >= probe * 95 / 100;
    };
    const std::vector<Role> xyz = {Role::x, Role::y, Role::z}, normal = {Role::nx, Role::ny, Role::nz}, rgb = {Role::r, Role::g, Role::b};
    auto cat = [](std::initializer_list<std::vector<Role>> parts) {
      std::vector<Role> all;
      for (const auto& p : parts) all.insert(all.end(), p.begin(), p.end());
      return all;
    };
    const std::vector<Role> intensity = {Role::skip};
    if (ncols == 3) roles = xyz;
    else if (ncols == 4) roles = cat({xyz, intensity});
    else if (ncols == 6 && looks_like_normal(3)) roles = cat({xyz, normal});
    else if (ncols == 6 && looks_like_colour(3)) roles = cat({xyz, rgb});
    else if (ncols == 7 && looks_like_colour(4)) roles = cat({xyz, intensity, rgb});  // .pts: x y z intensity r g b
    else if (ncols == 7 && looks_like_colour(3)) roles = cat({xyz, rgb, intensity});
    else if (ncols == 7 && looks_like_normal(3)) roles = cat({xyz, normal, intensity});
    else if (ncols == 9 && looks_like_normal(3) && looks_like_colour(6)) roles = cat({xyz, normal, rgb});
    else if (ncols == 9 && looks_like_colour(3) && looks_like_normal(6)) roles = cat({xyz, rgb, normal});
    if (roles.empty())
      throw InputError(file + ": cannot tell what the " + std::to_string(ncols) +
                       " columns hold (only x y z, plus unit normals, 0-255 colours or an intensity, are recognised); "
                       "name them with --columns, e.g. --columns x,y,z,i,r,g,b (i = intensity, _ = skip)");
    if (ncols >= 6) warnings.push_back(file + ": columns read as " + role_list(roles) + " (give --columns to change)");
  }
  int where[9];
  std::fill(std::begin(where), std::end(where), -1);
  for (std::size_t c = 0; c < roles.size(); ++c)
    if (roles[c] != Role::skip) {
      int& slot = where[static_cast<int>(roles[c])];
      if (slot >= 0) throw InputError(file + ": column " + std::to_string(c + 1) + " repeats the role of column " + std::to_string(slot + 1));
      slot = static_cast<int>(c);
    }
  if (where[0] < 0 || where[1] < 0 || where[2] < 0) throw InputError(file + ": the columns " + role_list(roles) + " do not include x, y and z");
  const bool normals = where[3] >= 0 && where[4] >= 0 && where[5] >= 0;
  const bool colours = where[6] >= 0 && where[7] >= 0 && where[8] >= 0;

  PointCloud cloud;
  std::vector<Vec3> rgb;
  walk(false, [&](std::size_t line_no, const std::vector<std::string_view>& values) {
    if (values.size() != roles.size())
      throw InputError(file + ":" + std::to_string(line_no) + ": " + std::to_string(values.size()) + " columns, expected " +
                       std::to_string(roles.size()) + " (" + role_list(roles) + ")");
    auto get = [&](int role) {
      double v = 0.0;
      const std::string_view t = values[static_cast<std::size_t>(where[role])];
      const Parsed p = number(t, v);
      if (p == Parsed::too_large) throw InputError(file + ":" + std::to_string(line_no) + ": '" + std::string(t.substr(0, 30)) + "' is too large");
      if (p != Parsed::ok) throw InputError(file + ":" + std::to_string(line_no) + ": '" + std::string(t.substr(0, 30)) + "' is not a number");
      return v;
    };
    cloud.points.emplace_back(get(0), get(1), get(2));
    if (normals) cloud.normals.emplace_back(get(3), get(4), get(5));
    if (colours) rgb.emplace_back(get(6), get(7), get(8));
    return true;
  });
  if (colours) {
    // Fractions in [0, 1] are scaled to bytes; byte values are kept.
    bool fractions = true;
    for (const auto& c : rgb) fractions = fractions && (c.array() <= 1.0).all();
    for (const auto& c : rgb) {
      const Vec3 v = (fractions ? Vec3(255.0 * c) : c).cwiseMax(0.0).cwiseMin(255.0);
      cloud.colours.push_back({static_cast<std::uint8_t>(std::lround(v.x())), static_cast<std::uint8_t>(std::lround(v.y())),
                               static_cast<std::uint8_t>(std::lround(v.z()))});
    }
  }
  if (announced >= 0 && static_cast<std::size_t>(announced) != cloud.points.size())
    warnings.push_back(file + ": the first line announces " + std::to_string(announced) + " points, the file has " +
                       std::to_string(cloud.points.size()));
  cloud.width = static_cast<int>(cloud.points.size());
  return cloud;
}

}  // namespace scanmesh::detail
