#include "binder.h"

#include <algorithm>

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

std::string Where::prefix(int at_line) const {
  std::string s = (file.empty() ? std::string() : file + ":" + std::to_string(at_line > 0 ? at_line : line) + ": ") + "stage " +
                  std::to_string(index + 1) + " '" + type + "'";
  if (!tag.empty()) s += " (tag '" + tag + "')";
  return s;
}

YAML::Node Binder::take(const std::string& key) {
  if (!active_ || !node_ || !node_.IsMap()) return YAML::Node();
  const YAML::Node& map = node_;  // const lookup: yaml-cpp's non-const operator[] would insert the key
  const YAML::Node n = map[key];
  if (!n || n.IsNull()) return YAML::Node();
  used_.insert(key);
  return n;
}

void Binder::fail(const YAML::Node& n, const std::string& key, const std::string& what) const {
  if (where_.file.empty()) {  // built from a command line: name the flag
    FieldInfo f;
    f.name = key;
    throw ConfigError(f.flag() + ": " + what);
  }
  throw ConfigError(where_.prefix(n.Mark().line + 1) + ": key '" + key + "': " + what);
}

void Binder::options(OptionSet& set) {
  struct Record {  // whatever happens below, the values as they end up are recorded
    Binder& b;
    OptionSet& s;
    ~Record() { b.record(s); }
  } record{*this, set};
  for (std::size_t i = 0; i < set.size(); ++i) {
    const FieldInfo& f = set.info(i);
    names_.push_back(f.name);
    fields_.push_back({f, set.default_value(i)});
    const YAML::Node n = take(f.name);
    if (!n.IsDefined() || n.IsNull()) continue;  // absent (take() returns a null node then)
    std::string text;
    if (n.IsScalar()) {
      text = n.Scalar();
    } else if ((f.type == FieldType::vec3 || f.type == FieldType::matrix4) && n.IsSequence()) {
      // Numbers, or for a matrix also rows of numbers; the schema checks the count.
      text = "[";
      bool first = true;
      auto add = [&](const YAML::Node& x) {
        if (!x.IsScalar()) fail(n, f.name, "expected " + f.domain());
        text += (first ? "" : ", ") + x.Scalar();
        first = false;
      };
      for (std::size_t k = 0; k < n.size(); ++k) {
        if (f.type == FieldType::matrix4 && n[k].IsSequence())
          for (std::size_t j = 0; j < n[k].size(); ++j) add(n[k][j]);
        else add(n[k]);
      }
      text += "]";
    } else {
      fail(n, f.name, "expected " + f.domain() + ", got a " + (n.IsSequence() ? "list" : "map"));
    }
    try {
      set.set(i, text);
    } catch (const UsageError& e) {
      // The schema's message starts with the flag ("--sigma-s: ..."); here the key is named instead.
      std::string what = e.what();
      const std::string flag = f.flag() + ": ";
      if (what.rfind(flag, 0) == 0) what = what.substr(flag.size());
      if (f.type == FieldType::choice) what = did_you_mean(text, f.choices) + what;
      fail(n, f.name, what);
    }
  }
}

void Binder::record(const OptionSet& set) {
  for (std::size_t i = 0; i < set.size(); ++i) resolved_.emplace_back(set.info(i).name, set.get(i));
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
