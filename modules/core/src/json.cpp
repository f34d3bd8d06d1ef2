#include "scanmesh/json.h"

#include <cmath>
#include <cstdio>

#include "scanmesh/schema.h"

namespace scanmesh {

std::string json_quote(std::string_view text) {
  std::string o = "\"";
  for (char c : text) {
    switch (c) {
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      case '\r': o += "\\r"; break;
      case '\t': o += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char b[8];
          std::snprintf(b, sizeof b, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
          o += b;
        } else {
          o += c;
        }
    }
  }
  return o + "\"";
}

void JsonWriter::newline(std::size_t depth) {
  out_ += '\n';
  out_.append(depth * static_cast<std::size_t>(indent_), ' ');
}

void JsonWriter::before_value(bool container) {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (stack_.empty()) return;
  Level& l = stack_.back();
  if (!l.first) out_ += ',';
  if (l.object || container || l.multiline) {
    l.multiline = true;
    newline(stack_.size());
  } else if (!l.first) {
    out_ += ' ';
  }
  l.first = false;
}

JsonWriter& JsonWriter::begin_object() {
  before_value(true);
  out_ += '{';
  stack_.push_back({true, true, true});
  return *this;
}

JsonWriter& JsonWriter::end_object() {
  const bool empty = stack_.back().first;
  stack_.pop_back();
  if (!empty) newline(stack_.size());
  out_ += '}';
  if (stack_.empty()) out_ += '\n';
  return *this;
}

JsonWriter& JsonWriter::begin_array() {
  before_value(true);
  out_ += '[';
  stack_.push_back({false, true, false});
  return *this;
}

JsonWriter& JsonWriter::end_array() {
  const bool multiline = stack_.back().multiline;
  stack_.pop_back();
  if (multiline) newline(stack_.size());
  out_ += ']';
  if (stack_.empty()) out_ += '\n';
  return *this;
}

JsonWriter& JsonWriter::key(std::string_view name) {
  Level& l = stack_.back();
  if (!l.first) out_ += ',';
  l.first = false;
  newline(stack_.size());
  out_ += json_quote(name);
  out_ += ": ";
  after_key_ = true;
  return *this;
}

JsonWriter& JsonWriter::value(std::string_view text) {
  before_value(false);
  out_ += json_quote(text);
  return *this;
}

JsonWriter& JsonWriter::value(double number) {
  before_value(false);
  out_ += std::isfinite(number) ? format_number(number) : "null";
  return *this;
}

JsonWriter& JsonWriter::value(long long number) {
  before_value(false);
  out_ += std::to_string(number);
  return *this;
}

JsonWriter& JsonWriter::value(unsigned long long number) {
  before_value(false);
  out_ += std::to_string(number);
  return *this;
}

JsonWriter& JsonWriter::value(bool flag) {
  before_value(false);
  out_ += flag ? "true" : "false";
  return *this;
}

JsonWriter& JsonWriter::null() {
  before_value(false);
  out_ += "null";
  return *this;
}

JsonWriter& JsonWriter::raw(std::string_view json) {
  before_value(false);
  out_ += json;
  return *this;
}

JsonWriter& JsonWriter::numbers(std::string_view name, const std::vector<double>& values) {
  key(name);
  begin_array();
  for (double v : values) value(v);
  return end_array();
}

}  // namespace scanmesh
