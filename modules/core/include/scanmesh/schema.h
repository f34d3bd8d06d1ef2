#pragma once
// Options described once. Every options struct has a Schema beside it that lists each field's name,
// unit, range and one-line doc (its default is the struct's own initializer); validation, the YAML
// pipeline binder, the command line, --help, the README's options tables and the JSON sidecar all read
// that one description. A field's YAML key is its name; its command-line flag is the name with '-' for
// '_' ("sigma_s" <-> "--sigma-s").
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "scanmesh/errors.h"
#include "scanmesh/length.h"
#include "scanmesh/mesh.h"

namespace scanmesh {

/// What kind of value a field holds (how it is parsed and printed).
enum class FieldType { number, integer, seed, flag, choice, length, vec3, matrix4, text };

/// A closed or open interval of allowed values for numbers and integers.
struct Range {
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  [[nodiscard]] bool contains(double x) const {
    return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
  }
  /// "(0, 2]", "[0, 1]", ">= 0"
  [[nodiscard]] std::string str() const;
};
/// [lo, hi]
inline Range closed(double lo, double hi) { return {lo, hi, false, false}; }
/// (lo, hi]
inline Range open_closed(double lo, double hi) { return {lo, hi, true, false}; }
/// >= lo
inline Range at_least(double lo) { return {lo, std::numeric_limits<double>::infinity(), false, false}; }

/// The description of one field.
struct FieldInfo {
  std::string name;  ///< YAML key, snake_case
  FieldType type = FieldType::number;
  std::string unit;  ///< "unitless", "x c_a", "degrees", "count", "length" (N*spacing, N*edge, N% or absolute) ...
  Range range;
  std::vector<std::string> choices;  ///< for FieldType::choice
  std::string doc;                   ///< one line
  [[nodiscard]] std::string flag() const;  ///< "--sigma-s"
  /// "unitless, (0, 2]" / "tukey | gaussian | ..." / "true | false": what the value may be.
  [[nodiscard]] std::string domain() const;
};

/// Canonical text of values (shortest round-trip numbers), as written in help, tables and sidecars.
std::string format_number(double v);

/// Parsing of a field's text value; throws UsageError("... must be in (0, 2], got 3") naming `flag`.
double parse_number_value(const FieldInfo& f, const std::string& text);
long long parse_integer_value(const FieldInfo& f, const std::string& text);
bool parse_flag_value(const FieldInfo& f, const std::string& text);
/// Throws UsageError naming the flag unless v is finite and within f.range.
void check_number_value(const FieldInfo& f, double v);
Vec3 parse_vec3_value(const FieldInfo& f, const std::string& text);
/// A rigid transform as 16 numbers, row by row (nested lists allowed); throws unless it is one.
Eigen::Matrix4d parse_matrix4_value(const FieldInfo& f, const std::string& text);
/// "[1, 0, 0, 0, ...]" (row by row).
std::string format_matrix4(const Eigen::Matrix4d& m);

/// The fields of one options struct O, each with typed access to an O.
template <class O>
class Schema {
 public:
  struct Field {
    FieldInfo info;
    std::function<std::string(const O&)> get;
    std::function<void(O&, const std::string&)> set;  ///< parses and range-checks, throws UsageError
    std::function<void(const O&)> check;              ///< throws UsageError if the value is out of range
  };

  Schema& number(const char* name, double O::*m, Range r, const char* unit, const char* doc) {
    FieldInfo fi{name, FieldType::number, unit, r, {}, doc};
    fields_.push_back({fi, [m](const O& o) { return format_number(o.*m); },
                       [m, fi](O& o, const std::string& t) { o.*m = parse_number_value(fi, t); },
                       [m, fi](const O& o) { check_number_value(fi, o.*m); }});
    return *this;
  }
  Schema& integer(const char* name, int O::*m, Range r, const char* unit, const char* doc) {
    FieldInfo fi{name, FieldType::integer, unit, r, {}, doc};
    fields_.push_back({fi, [m](const O& o) { return std::to_string(o.*m); },
                       [m, fi](O& o, const std::string& t) { o.*m = static_cast<int>(parse_integer_value(fi, t)); },
                       [m, fi](const O& o) { check_number_value(fi, o.*m); }});
    return *this;
  }
  Schema& seed(const char* name, std::uint64_t O::*m, const char* doc) {
    FieldInfo fi{name, FieldType::seed, "whole number", at_least(0), {}, doc};
    fields_.push_back({fi, [m](const O& o) { return std::to_string(o.*m); },
                       [m, fi](O& o, const std::string& t) {
                         std::uint64_t v = 0;
                         auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
                         if (ec != std::errc() || p != t.data() + t.size())
                           throw UsageError(fi.flag() + ": expected a non-negative whole number, got '" + t + "'");
                         o.*m = v;
                       },
                       [](const O&) {}});
    return *this;
  }
  Schema& flag(const char* name, bool O::*m, const char* doc) {
    FieldInfo fi{name, FieldType::flag, "switch", {}, {}, doc};
    fields_.push_back({fi, [m](const O& o) { return std::string(o.*m ? "true" : "false"); },
                       [m, fi](O& o, const std::string& t) { o.*m = parse_flag_value(fi, t); }, [](const O&) {}});
    return *this;
  }
  template <class E>
  Schema& choice(const char* name, E O::*m, std::vector<std::pair<std::string, E>> values, const char* doc) {
    FieldInfo fi{name, FieldType::choice, "choice", {}, {}, doc};
    for (const auto& v : values) fi.choices.push_back(v.first);
    fields_.push_back({fi,
                       [m, values](const O& o) {
                         for (const auto& v : values)
                           if (v.second == o.*m) return v.first;
                         return std::string("?");
                       },
                       [m, values, fi](O& o, const std::string& t) {
                         for (const auto& v : values)
                           if (v.first == t) {
                             o.*m = v.second;
                             return;
                           }
                         throw UsageError(fi.flag() + ": '" + t + "' is not a valid choice; choose " + fi.domain());
                       },
                       [](const O&) {}});
    return *this;
  }
  Schema& length(const char* name, Length O::*m, Range r, const char* doc) {
    FieldInfo fi{name, FieldType::length, "length", r, {}, doc};
    fields_.push_back({fi, [m](const O& o) { return (o.*m).str(); },
                       [m, fi](O& o, const std::string& t) {
                         Length l = parse_length(t, fi.flag());
                         if (!fi.range.contains(l.value))
                           throw UsageError(fi.flag() + ": must be in " + fi.range.str() + ", got " + t);
                         o.*m = l;
                       },
                       [m, fi](const O& o) {
                         if (!fi.range.contains((o.*m).value))
                           throw UsageError(fi.flag() + ": must be in " + fi.range.str() + ", got " + (o.*m).str());
                       }});
    return *this;
  }
  Schema& vec3(const char* name, Vec3 O::*m, const char* unit, const char* doc) {
    FieldInfo fi{name, FieldType::vec3, unit, {}, {}, doc};
    fields_.push_back({fi,
                       [m](const O& o) {
                         return "[" + format_number((o.*m)[0]) + ", " + format_number((o.*m)[1]) + ", " + format_number((o.*m)[2]) + "]";
                       },
                       [m, fi](O& o, const std::string& t) { o.*m = parse_vec3_value(fi, t); }, [](const O&) {}});
    return *this;
  }
  Schema& matrix4(const char* name, Eigen::Matrix4d O::*m, const char* unit, const char* doc) {
    FieldInfo fi{name, FieldType::matrix4, unit, {}, {}, doc};
    fields_.push_back({fi, [m](const O& o) { return format_matrix4(o.*m); },
                       [m, fi](O& o, const std::string& t) { o.*m = parse_matrix4_value(fi, t); }, [](const O&) {}});
    return *this;
  }
  Schema& text(const char* name, std::string O::*m, const char* unit, const char* doc) {
    FieldInfo fi{name, FieldType::text, unit, {}, {}, doc};
    fields_.push_back({fi, [m](const O& o) { return o.*m; }, [m](O& o, const std::string& t) { o.*m = t; }, [](const O&) {}});
    return *this;
  }

  [[nodiscard]] const std::vector<Field>& fields() const { return fields_; }
  [[nodiscard]] const Field* find(const std::string& name) const {
    for (const auto& f : fields_)
      if (f.info.name == name) return &f;
    return nullptr;
  }
  /// Throws UsageError naming the first field whose value is out of its range.
  void validate(const O& o) const {
    for (const auto& f : fields_) f.check(o);
  }

 private:
  std::vector<Field> fields_;
};

/// A live options object seen through its schema, without its type: what the pipeline, the command
/// line and the sidecar work with.
class OptionSet {
 public:
  virtual ~OptionSet() = default;
  [[nodiscard]] virtual std::size_t size() const = 0;
  [[nodiscard]] virtual const FieldInfo& info(std::size_t i) const = 0;
  [[nodiscard]] virtual std::string get(std::size_t i) const = 0;
  /// Parses and stores a value (throws UsageError naming the flag); marks the field as given.
  virtual void set(std::size_t i, const std::string& text) = 0;
  virtual void validate() const = 0;
  /// The default value's text (from a default-constructed struct).
  [[nodiscard]] virtual std::string default_value(std::size_t i) const = 0;
  /// Index of the field called `name`, or -1.
  [[nodiscard]] long find(const std::string& name) const {
    for (std::size_t i = 0; i < size(); ++i)
      if (info(i).name == name) return static_cast<long>(i);
    return -1;
  }
  /// True if set() gave this field a value (explicit values win over automatic choices).
  [[nodiscard]] bool given(const std::string& name) const {
    const long i = find(name);
    return i >= 0 && given_.size() > static_cast<std::size_t>(i) && given_[static_cast<std::size_t>(i)];
  }

 protected:
  std::vector<bool> given_;
};

/// OptionSet over an O stored elsewhere (the stage or command that owns it).
template <class O>
class BoundOptions final : public OptionSet {
 public:
  BoundOptions(O& object, const Schema<O>& schema) : o_(object), s_(schema) { given_.assign(schema.fields().size(), false); }
  [[nodiscard]] std::size_t size() const override { return s_.fields().size(); }
  [[nodiscard]] const FieldInfo& info(std::size_t i) const override { return s_.fields()[i].info; }
  [[nodiscard]] std::string get(std::size_t i) const override { return s_.fields()[i].get(o_); }
  void set(std::size_t i, const std::string& text) override {
    s_.fields()[i].set(o_, text);
    given_[i] = true;
  }
  void validate() const override { s_.validate(o_); }
  [[nodiscard]] std::string default_value(std::size_t i) const override { return s_.fields()[i].get(O{}); }

 private:
  O& o_;
  const Schema<O>& s_;
};

}  // namespace scanmesh
