#pragma once
// A small streaming JSON writer: what `eval --json`, the report sidecar and the benches write with, so
// escaping, number formatting (shortest round trip, null for NaN and infinity) and layout exist once.
// Objects are laid out one member per line; arrays of plain values stay on one line.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace scanmesh {

class JsonWriter {
 public:
  explicit JsonWriter(int indent = 2) : indent_(indent) {}

  JsonWriter& begin_object();
  JsonWriter& end_object();
  JsonWriter& begin_array();
  JsonWriter& end_array();
  /// The next member's name (inside an object).
  JsonWriter& key(std::string_view name);

  JsonWriter& value(std::string_view text);
  JsonWriter& value(const char* text) { return value(std::string_view(text)); }
  JsonWriter& value(const std::string& text) { return value(std::string_view(text)); }
  JsonWriter& value(double number);  ///< null if not finite
  JsonWriter& value(long long number);
  JsonWriter& value(unsigned long long number);
  JsonWriter& value(int number) { return value(static_cast<long long>(number)); }
  JsonWriter& value(unsigned number) { return value(static_cast<unsigned long long>(number)); }
  JsonWriter& value(unsigned long number) { return value(static_cast<unsigned long long>(number)); }
  JsonWriter& value(long number) { return value(static_cast<long long>(number)); }
  JsonWriter& value(bool flag);
  JsonWriter& null();
  /// Inserts an already written JSON value verbatim (must be valid JSON).
  JsonWriter& raw(std::string_view json);

  /// key(name).value(v) in one call.
  template <class T>
  JsonWriter& field(std::string_view name, const T& v) {
    key(name);
    return value(v);
  }
  /// An array of numbers on one line.
  JsonWriter& numbers(std::string_view name, const std::vector<double>& values);

  /// The document (ends with a newline once the outermost value is closed).
  [[nodiscard]] const std::string& str() const { return out_; }

 private:
  struct Level {
    bool object = false;
    bool first = true;
    bool multiline = false;
  };
  void before_value(bool container);
  void newline(std::size_t depth);
  std::string out_;
  std::vector<Level> stack_;
  bool after_key_ = false;
  int indent_;
};

/// `text` as a JSON string literal, quotes included.
std::string json_quote(std::string_view text);

}  // namespace scanmesh
