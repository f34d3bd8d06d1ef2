#include "scanmesh/schema.h"

#include <algorithm>
#include <cctype>

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

Vec3 parse_vec3_value(const FieldInfo& f, const std::string& text) {
  // "[x, y, z]", "x,y,z" or "x y z".
  std::string t = text;
  for (char& c : t)
    if (c == '[' || c == ']' || c == ',') c = ' ';
  Vec3 v;
  std::size_t pos = 0;
  for (int k = 0; k < 3; ++k) {
    while (pos < t.size() && t[pos] == ' ') ++pos;
    const std::size_t end = std::min(t.find(' ', pos), t.size());
    double x = 0.0;
    auto [p, ec] = std::from_chars(t.data() + pos, t.data() + end, x);
    if (pos >= t.size() || ec != std::errc() || p != t.data() + end || !std::isfinite(x))
      throw UsageError(f.flag() + ": expected three numbers, e.g. [0, 0, 0], got '" + text + "'");
    v[k] = x;
    pos = end;
  }
  while (pos < t.size() && t[pos] == ' ') ++pos;
  if (pos != t.size()) throw UsageError(f.flag() + ": expected three numbers, e.g. [0, 0, 0], got '" + text + "'");
  return v;
}

}  // namespace scanmesh
