#pragma once
// A small, fast cursor over a text file held in memory, used by the OBJ, OFF, PLY and STL parsers.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <string>
#include <string_view>

#include "scanmesh/atomic_file.h"
#include "scanmesh/errors.h"

namespace scanmesh::detail {

class TextScanner {
 public:
  /// `first_line`: the line number of the text's first line (when a file is parsed a block at a time).
  TextScanner(std::string_view text, std::string file, std::size_t first_line = 1)
      : text_(text), file_(std::move(file)), line_(first_line) {}

  [[nodiscard]] bool at_end() const { return pos_ >= text_.size(); }
  /// Ends the text at `end` (a streamed file's window up to its last whole line).
  void limit(std::size_t end) { text_ = text_.substr(0, std::max(end, pos_)); }
  /// Goes on in `text`, the next block of the same file: from its start, the line count carried on.
  void continue_on(std::string_view text) {
    text_ = text;
    pos_ = 0;
  }
  [[nodiscard]] std::size_t line() const { return line_; }
  [[nodiscard]] std::size_t position() const { return pos_; }
  [[nodiscard]] const std::string& file() const { return file_; }

  /// Skips spaces and tabs (and '\r'), not newlines.
  void skip_blanks() {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\r')) ++pos_;
  }
  /// Skips all whitespace including newlines, and '#' comments if `comments`.
  void skip_space(bool comments) {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        ++line_;
        ++pos_;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
        ++pos_;
      } else if (comments && c == '#') {
        skip_line();
      } else {
        break;
      }
    }
  }
  /// Moves past the end of the current line.
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    if (pos_ < text_.size()) {
      ++pos_;
      ++line_;
    }
  }
  /// True if the rest of the current line is blank.
  [[nodiscard]] bool at_line_end() {
    skip_blanks();
    return pos_ >= text_.size() || text_[pos_] == '\n' || text_[pos_] == '#';
  }
  /// Next whitespace-delimited token on the current line (empty at line end).
  std::string_view token() {
    skip_blanks();
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  /// Next token anywhere (crossing lines), empty at end of file.
  std::string_view any_token(bool comments) {
    skip_space(comments);
    return token();
  }

  /// Parses a whole token as a double. "nan"/"inf" spellings are accepted as such (callers decide whether
  /// non-finite values are allowed); a number too large for a double is rejected, one too small becomes
  /// the nearest representable value (0 or a denormal).
  bool parse_double(std::string_view tok, double& out) const { return parse_number(tok, out) == NumberStatus::ok; }

  enum class NumberStatus { ok, not_a_number, out_of_range };
  static NumberStatus parse_number(std::string_view tok, double& out) {
    if (tok.empty()) return NumberStatus::not_a_number;
    const char* b = tok.data();
    const char* e = b + tok.size();
    if (*b == '+') ++b;
    auto [p, ec] = std::from_chars(b, e, out);
    if (p != e) return NumberStatus::not_a_number;
    if (ec == std::errc::result_out_of_range) {
      // from_chars leaves `out` untouched here; strtod tells overflow (+-HUGE_VAL) from underflow (a
      // denormal or zero, which is kept).
      const std::string copy(b, e);
      const double v = std::strtod(copy.c_str(), nullptr);
      if (std::isinf(v)) return NumberStatus::out_of_range;
      out = v;
      return NumberStatus::ok;
    }
    return ec == std::errc() ? NumberStatus::ok : NumberStatus::not_a_number;
  }

  /// Parses a finite number or fails with "FILE:LINE: <what>: 'tok' is not a number" (or "is too large").
  double finite_number(std::string_view tok, const std::string& what) const {
    double v = 0.0;
    if (tok.empty()) fail(what + ": missing number (truncated?)");
    const NumberStatus st = parse_number(tok, v);
    const std::string shown(tok.substr(0, 30));
    if (st == NumberStatus::out_of_range) fail(what + ": '" + shown + "' is too large for a double");
    if (st != NumberStatus::ok) fail(what + ": '" + shown + "' is not a number");
    if (!std::isfinite(v)) fail(what + ": '" + shown + "' is not a finite number (NaN or infinite)");
    return v;
  }

  bool parse_int(std::string_view tok, long long& out) const {
    if (tok.empty()) return false;
    const char* b = tok.data();
    const char* e = b + tok.size();
    if (*b == '+') ++b;
    auto [p, ec] = std::from_chars(b, e, out);
    return ec == std::errc() && p == e;
  }

  /// Throws InputError "FILE:LINE: message".
  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(file_ + ":" + std::to_string(line_) + ": " + message);
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
  std::string_view text_;
  std::string file_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
};

/// Appends the shortest round-trip decimal form of v.
inline void append_double(std::string& out, double v) {
  char buf[32];
  auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, static_cast<std::size_t>(p - buf));
}
inline void append_int(std::string& out, long long v) {
  char buf[24];
  auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, static_cast<std::size_t>(p - buf));  // (pointer, size): GCC 12 warns falsely on the iterator form
}

/// Writers stream their files: they build a piece in a string and hand it to the sink (emptying the
/// string) whenever it holds a megabyte, so a file is never held whole in memory.
constexpr std::size_t kWriteChunk = std::size_t{1} << 20;
inline void flush_if_full(std::string& out, const ByteSink& sink) {
  if (out.size() < kWriteChunk) return;
  sink(out);
  out.clear();
}

/// Appends "3 a b c" lines (0-based indices), the face list of OFF and ascii PLY, streaming as above.
template <typename Faces>
void append_counted_faces(std::string& out, const Faces& faces, const ByteSink& sink) {
  for (const auto& f : faces) {
    out += "3 ";
    for (int k = 0; k < 3; ++k) {
      append_int(out, f[k]);
      out += k < 2 ? ' ' : '\n';
    }
    flush_if_full(out, sink);
  }
}

}  // namespace scanmesh::detail
