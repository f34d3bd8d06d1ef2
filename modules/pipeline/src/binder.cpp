#include "binder.h"

#include <algorithm>
#include <cmath>

namespace scanmesh::detail {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = 1000;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  if (!best.empty() && best_d <= std::max<std::size_t>(2, word.size() / 3)) return "did you mean '" + best + "'? ";
  return "";
}

std::string join(const std::vector<std::string>& items) {
  std::string s;
  for (std::size_t i = 0; i < items.size(); ++i) s += (i ? ", " : "") + items[i];
  return s;
}

YAML::Node Binder::take(const char* key) {
  if (!active_ || !node_ || !node_.IsMap()) return YAML::Node();
  const YAML::Node& map = node_;  // const lookup: yaml-cpp's non-const operator[] would insert the key
  const YAML::Node n = map[key];
  if (!n || n.IsNull()) return YAML::Node();
  used_.insert(key);
  return n;
}

void Binder::fail(const YAML::Node& n, const std::string& key, const std::string& what) const {
  throw ConfigError(where_.prefix(n.Mark().line + 1) + ": key '" + key + "': " + what);
}

void Binder::number(const char* key, double& v, double lo, double hi) {
  names_.emplace_back(key);
  const YAML::Node n = take(key);
  if (!n || n.IsNull()) return;
  double x = 0.0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, x) || !std::isfinite(x))
    fail(n, key, "expected a number, got '" + (n.IsScalar() ? n.Scalar() : std::string("a list or map")) + "'");
  if (x < lo || x > hi) fail(n, key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + n.Scalar());
  v = x;
}

void Binder::integer(const char* key, int& v, int lo, int hi) {
  names_.emplace_back(key);
  const YAML::Node n = take(key);
  if (!n || n.IsNull()) return;
  int x = 0;
  if (!n.IsScalar() || !YAML::convert<int>::decode(n, x))
    fail(n, key, "expected a whole number, got '" + (n.IsScalar() ? n.Scalar() : std::string("a list or map")) + "'");
  if (x < lo || x > hi) fail(n, key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + n.Scalar());
  v = x;
}

void Binder::seed(const char* key, std::uint64_t& v) {
  names_.emplace_back(key);
  const YAML::Node n = take(key);
  if (!n || n.IsNull()) return;
  unsigned long long x = 0;
  if (!n.IsScalar() || !YAML::convert<unsigned long long>::decode(n, x))
    fail(n, key, "expected a non-negative whole number, got '" + (n.IsScalar() ? n.Scalar() : std::string("a list or map")) + "'");
  v = x;
}

void Binder::flag(const char* key, bool& v) {
  names_.emplace_back(key);
  const YAML::Node n = take(key);
  if (!n || n.IsNull()) return;
  bool x = false;
  if (!n.IsScalar() || !YAML::convert<bool>::decode(n, x))
    fail(n, key, "expected true or false, got '" + (n.IsScalar() ? n.Scalar() : std::string("a list or map")) + "'");
  v = x;
}

void Binder::text(const char* key, std::string& v) {
  names_.emplace_back(key);
  const YAML::Node n = take(key);
  if (!n || n.IsNull()) return;
  if (!n.IsScalar()) fail(n, key, "expected a text value");
  v = n.Scalar();
}

void Binder::length(const char* key, Length& v) {
  names_.emplace_back(key);
  const YAML::Node n = take(key);
  if (!n || n.IsNull()) return;
  if (!n.IsScalar()) fail(n, key, "expected a length (a number, N*spacing, N*edge or N%)");
  try {
    v = parse_length(n.Scalar(), key);
  } catch (const UsageError&) {
    fail(n, key, "'" + n.Scalar() + "' is not a length; use a number (scene units), N*spacing, N*edge or N%");
  }
}

void Binder::vec3(const char* key, Vec3& v) {
  names_.emplace_back(key);
  const YAML::Node n = take(key);
  if (!n || n.IsNull()) return;
  if (!n.IsSequence() || n.size() != 3) fail(n, key, "expected three numbers, e.g. [0, 0, 0]");
  for (int c = 0; c < 3; ++c)
    if (!n[c].IsScalar() || !YAML::convert<double>::decode(n[c], v[c])) fail(n, key, "expected three numbers, e.g. [0, 0, 0]");
}

void Binder::finish() const {
  if (!active_ || !node_ || !node_.IsMap()) return;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const std::string key = it->first.Scalar();
    if (used_.count(key) || key == "type" || key == "tag" || key == "inputs") continue;
    throw ConfigError(where_.prefix(it->first.Mark().line + 1) + ": unknown option '" + key + "'; " + did_you_mean(key, names_) +
                      "valid: " + (names_.empty() ? std::string("(none)") : join(names_)));
  }
}

}  // namespace scanmesh::detail
