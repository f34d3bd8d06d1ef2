#pragma once
// Reads a stage's YAML options into its options struct, field by field; the same field list serves as the
// schema (names for "did you mean" and help). Errors carry FILE:LINE, the stage and the key.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "scanmesh/length.h"
#include "scanmesh/mesh.h"
#include "scanmesh/pipeline.h"

namespace scanmesh::detail {

/// Where a stage is, for messages.
struct Where {
  std::string file;
  int line = 0;  ///< 1-based
  int index = 0;
  std::string type, tag;
  [[nodiscard]] std::string prefix(int at_line = 0) const {
    std::string s = file + ":" + std::to_string(at_line > 0 ? at_line : line) + ": stage " + std::to_string(index + 1) + " '" + type + "'";
    if (!tag.empty()) s += " (tag '" + tag + "')";
    return s;
  }
};

/// Levenshtein distance, for suggestions.
std::size_t edit_distance(const std::string& a, const std::string& b);
/// "did you mean 'x'? " if a candidate is close, else "".
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);
std::string join(const std::vector<std::string>& items);

class Binder {
 public:
  /// Schema mode (no node): only collects names.
  Binder() = default;
  Binder(YAML::Node options, Where where) : node_(std::move(options)), where_(std::move(where)), active_(true) {}

  void number(const char* key, double& v, double lo, double hi);
  void integer(const char* key, int& v, int lo, int hi);
  void seed(const char* key, std::uint64_t& v);
  void flag(const char* key, bool& v);
  void text(const char* key, std::string& v);
  void length(const char* key, Length& v);
  void vec3(const char* key, Vec3& v);
  template <typename E>
  void choice(const char* key, E& v, const std::vector<std::pair<std::string, E>>& choices) {
    names_.emplace_back(key);
    const YAML::Node n = take(key);
    if (!n || n.IsNull()) return;
    std::vector<std::string> valid;
    for (const auto& c : choices) valid.push_back(c.first);
    if (!n.IsScalar()) fail(n, key, "expected one of " + join(valid));
    const std::string s = n.Scalar();
    for (const auto& c : choices)
      if (c.first == s) {
        v = c.second;
        return;
      }
    fail(n, key, "'" + s + "' is not a valid choice; " + did_you_mean(s, valid) + "valid: " + join(valid));
  }
  /// True if the stage's YAML gives this key (to let explicit values win over automatic ones).
  [[nodiscard]] bool present(const char* key) const {
    if (!active_ || !node_ || !node_.IsMap()) return false;
    const YAML::Node& map = node_;
    return map[key] && !map[key].IsNull();
  }
  /// Throws for keys no field consumed.
  void finish() const;
  [[nodiscard]] const std::vector<std::string>& names() const { return names_; }

 private:
  YAML::Node take(const char* key);
  [[noreturn]] void fail(const YAML::Node& n, const std::string& key, const std::string& what) const;
  YAML::Node node_;
  Where where_;
  bool active_ = false;
  std::vector<std::string> names_;
  std::set<std::string> used_;
};

}  // namespace scanmesh::detail
