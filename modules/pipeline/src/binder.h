#pragma once
// Reads a stage's YAML map into its options through the options' schema (scanmesh/schema.h): each key is
// a field name, each value parsed and range-checked by the schema. Errors carry FILE:LINE, the stage and
// the key. Without a node (schema mode) a Binder only collects the names, for help and suggestions.
#include <yaml-cpp/yaml.h>

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "scanmesh/pipeline.h"
#include "scanmesh/schema.h"

namespace scanmesh::detail {

/// Where a stage is, for messages.
struct Where {
  std::string file;
  int line = 0;  ///< 1-based
  int index = 0;
  std::string type, tag;
  [[nodiscard]] std::string prefix(int at_line = 0) const;
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

  /// Reads every field of `set` the map gives.
  void options(OptionSet& set);
  /// Throws for keys no field consumed.
  void finish() const;
  [[nodiscard]] const std::vector<std::string>& names() const { return names_; }
  /// Every field met, with its default value's text (schema mode and binding alike).
  [[nodiscard]] const std::vector<StageOption>& fields() const { return fields_; }
  /// Every field met with the value it has after binding (given or default): the resolved configuration.
  [[nodiscard]] const std::vector<std::pair<std::string, std::string>>& resolved() const { return resolved_; }

 private:
  YAML::Node take(const std::string& key);
  void record(const OptionSet& set);
  [[noreturn]] void fail(const YAML::Node& n, const std::string& key, const std::string& what) const;
  YAML::Node node_;
  Where where_;
  bool active_ = false;
  std::vector<std::string> names_;
  std::vector<StageOption> fields_;
  std::vector<std::pair<std::string, std::string>> resolved_;
  std::set<std::string> used_;
};

}  // namespace scanmesh::detail
