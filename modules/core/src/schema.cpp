#include "scanmesh/schema.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <vector>

namespace scanmesh {

std::string format_number(double v) {
  char buf[32];
  auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, p);
}

std::string Range::str() const {
  const bool low = std::isfinite(lo), high = std::isfinite(hi);
  if (low && high) return std::string(lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) + (hi_open ? ")" : "]");
  if (low) return std::string(lo_open ? "> " : ">= ") + format_number(lo);
  if (high) return std::string(hi_open ? "< " : "<= ") + format_number(hi);
  return "any";
}

std::string FieldInfo::flag() const {
  std::string f = "--" + name;
  std::replace(f.begin(), f.end(), '_', '-');
  return f;
}

std::string FieldInfo::domain() const {
  switch (type) {
    case FieldType::choice: {
      std::string s;
      for (std::size_t i = 0; i < choices.size(); ++i) s += (i ? " | " : "") + choices[i];
      return s;
    }
    case FieldType::flag: return "true | false";
    case FieldType::text: return unit;
    case FieldType::vec3: return unit + ", [x, y, z]";
    case FieldType::matrix4: return unit + ", 16 numbers row by row";
    case FieldType::length: return "length (number, N*spacing, N*edge or N%), " + range.str();
    case FieldType::seed: return "whole number >= 0";
    default: return unit + ", " + range.str();
  }
}

void check_number_value(const FieldInfo& f, double v) {
  if (!std::isfinite(v) || !f.range.contains(v))
    throw UsageError(f.flag() + ": must be in " + f.range.str() + ", got " + format_number(v));
}

double parse_number_value(const FieldInfo& f, const std::string& text) {
  double v = 0.0;
  const char* b = text.data() + (!text.empty() && text[0] == '+' ? 1 : 0);
  auto [p, ec] = std::from_chars(b, text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || p != text.data() + text.size())
    throw UsageError(f.flag() + ": expected a number, got '" + text + "'");
  check_number_value(f, v);
  return v;
}

long long parse_integer_value(const FieldInfo& f, const std::string& text) {
  long long v = 0;
  const char* b = text.data() + (!text.empty() && text[0] == '+' ? 1 : 0);
  auto [p, ec] = std::from_chars(b, text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || p != text.data() + text.size())
    throw UsageError(f.flag() + ": expected a whole number, got '" + text + "'");
  check_number_value(f, static_cast<double>(v));
  return v;
}

bool parse_flag_value(const FieldInfo& f, const std::string& text) {
  std::string t = text;
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return std::tolower(c); });
  if (t == "true" || t == "yes" || t == "on" || t == "1") return true;
  if (t == "false" || t == "no" || t == "off" || t == "0") return false;
  throw UsageError(f.flag() + ": expected true or false, got '" + text + "'");
}

namespace {

// "[a, b, ...]", "a,b,..." or "a b ..." (nested brackets allowed): exactly `count` finite numbers.
std::vector<double> parse_numbers(const FieldInfo& f, const std::string& text, std::size_t count, const char* example) {
  std::string t = text;
  for (char& c : t)
    if (c == '[' || c == ']' || c == ',' || c == '\n' || c == '\t') c = ' ';
  std::vector<double> out;
  std::size_t pos = 0;
  while (true) {
    while (pos < t.size() && t[pos] == ' ') ++pos;
    if (pos >= t.size()) break;
    const std::size_t end = std::min(t.find(' ', pos), t.size());
    double x = 0.0;
    auto [p, ec] = std::from_chars(t.data() + pos, t.data() + end, x);
    if (ec != std::errc() || p != t.data() + end || !std::isfinite(x) || out.size() == count)
      throw UsageError(f.flag() + ": expected " + std::to_string(count) + " numbers, e.g. " + example + ", got '" + text + "'");
    out.push_back(x);
    pos = end;
  }
  if (out.size() != count)
    throw UsageError(f.flag() + ": expected " + std::to_string(count) + " numbers, e.g. " + example + ", got '" + text + "'");
  return out;
}

}  // namespace

Vec3 parse_vec3_value(const FieldInfo& f, const std::string& text) {
  const std::vector<double> v = parse_numbers(f, text, 3, "[0, 0, 0]");
  return Vec3(v[0], v[1], v[2]);
}

Eigen::Matrix4d parse_matrix4_value(const FieldInfo& f, const std::string& text) {
  const std::vector<double> v = parse_numbers(f, text, 16, "[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]");
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = v[static_cast<std::size_t>(4 * r + c)];
  if (std::abs(m(3, 0)) + std::abs(m(3, 1)) + std::abs(m(3, 2)) > 1e-12 || std::abs(m(3, 3) - 1.0) > 1e-12)
    throw UsageError(f.flag() + ": the last row of a rigid transform must be 0 0 0 1, got '" + text + "'");
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-4 || r.determinant() < 0.0)
    throw UsageError(f.flag() + ": the upper-left 3x3 block must be a rotation (orthonormal, determinant 1), got '" + text + "'");
  return m;
}

std::string format_matrix4(const Eigen::Matrix4d& m) {
  std::string s = "[";
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) s += (r + c ? ", " : "") + format_number(m(r, c));
  return s + "]";
}

}  // namespace scanmesh
