#include "scanmesh/length.h"

#include <charconv>
#include <cmath>
#include <sstream>

#include "scanmesh/errors.h"

namespace scanmesh {

double Length::resolve(double spacing, double edge, double diagonal) const {
  switch (unit) {
    case Unit::absolute: return value;
    case Unit::spacing: return value * spacing;
    case Unit::edge: return value * edge;
    case Unit::percent_of_diagonal: return value * diagonal / 100.0;
  }
  return value;
}

std::string Length::str() const {
  std::ostringstream o;
  o << value;
  switch (unit) {
    case Unit::absolute: break;
    case Unit::spacing: o << "*spacing"; break;
    case Unit::edge: o << "*edge"; break;
    case Unit::percent_of_diagonal: o << "%"; break;
  }
  return o.str();
}

Length parse_length(const std::string& text, const std::string& what) {
  auto fail = [&]() -> Length {
    throw UsageError(what + ": '" + text + "' is not a length; use a number (scene units), N*spacing, N*edge or N%");
  };
  auto number = [&](const std::string& s, double& v) {
    const char* b = s.data();
    const char* e = b + s.size();
    auto [p, ec] = std::from_chars(b, e, v);
    return ec == std::errc() && p == e && std::isfinite(v) && v >= 0.0;
  };
  Length l;
  std::string s = text;
  if (!s.empty() && s.back() == '%') {
    l.unit = Length::Unit::percent_of_diagonal;
    s.pop_back();
  } else if (const auto star = s.find('*'); star != std::string::npos) {
    const std::string unit = s.substr(star + 1);
    if (unit == "spacing") l.unit = Length::Unit::spacing;
    else if (unit == "edge") l.unit = Length::Unit::edge;
    else return fail();
    s = s.substr(0, star);
  }
  if (!number(s, l.value)) return fail();
  return l;
}

}  // namespace scanmesh
