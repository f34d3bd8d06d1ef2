// Object File Format: "OFF" (or "COFF" with per-vertex colours), counts, vertices, polygons.
#include <algorithm>
#include <cmath>

#include "formats.h"
#include "text_scanner.h"

namespace scanmesh::detail {

Mesh read_off(std::string_view data, const std::string& file, std::vector<std::string>& warnings) {
  TextScanner s(data, file);
  std::string_view magic = s.any_token(true);
  bool coloured = false;
  std::string_view first_count;
  if (magic == "OFF" || magic == "COFF" || magic == "NOFF" || magic == "CNOFF" || magic == "NCOFF") {
    coloured = magic.find('C') != std::string_view::npos;
    if (magic.find('N') != std::string_view::npos) s.fail("OFF with per-vertex normals (" + std::string(magic) + ") is not supported");
  } else if (magic.size() > 3 && magic.substr(0, 3) == "OFF") {
    s.fail("unsupported OFF variant '" + std::string(magic) + "'");
  } else {
    // The header keyword is optional in some writers; the first token must then be the vertex count.
    long long probe;
    if (!s.parse_int(magic, probe)) s.fail("not an OFF file: expected 'OFF' header, found '" + std::string(magic.substr(0, 20)) + "'");
    first_count = magic;
  }
  long long counts[3];
  for (int i = 0; i < 3; ++i) {
    const std::string_view tok = (i == 0 && !first_count.empty()) ? first_count : s.any_token(true);
    if (!s.parse_int(tok, counts[i]) || counts[i] < 0)
      s.fail("expected vertex, face and edge counts after the OFF header");
  }
  const long long nv = counts[0], nf = counts[1];
  if (nv > static_cast<long long>(data.size()) || nf > static_cast<long long>(data.size()))
    s.fail("vertex/face counts (" + std::to_string(nv) + ", " + std::to_string(nf) + ") are larger than the file could hold");
  Mesh mesh;
  mesh.positions.resize(static_cast<std::size_t>(nv));
  std::vector<double> rgb;
  for (long long v = 0; v < nv; ++v) {
    for (int c = 0; c < 3; ++c) {
      const std::string_view tok = s.any_token(true);
      if (tok.empty()) s.fail("file ends after " + std::to_string(v) + " of " + std::to_string(nv) + " vertices (truncated?)");
      mesh.positions[v][c] = s.finite_number(tok, "vertex " + std::to_string(v));
    }
    if (coloured) {
      for (int c = 0; c < 3; ++c) {
        double x;
        if (!s.parse_double(s.token(), x)) s.fail("COFF vertex " + std::to_string(v) + " needs a colour");
        rgb.push_back(x);
      }
    }
    s.skip_line();
  }
  std::size_t polygons_split = 0;
  std::vector<int> corners;
  for (long long f = 0; f < nf; ++f) {
    const std::string_view tok = s.any_token(true);
    long long n = 0;
    if (tok.empty()) s.fail("file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces (truncated?)");
    if (!s.parse_int(tok, n) || n < 3) s.fail("face " + std::to_string(f) + " must start with a corner count >= 3, found '" + std::string(tok) + "'");
    corners.clear();
    for (long long k = 0; k < n; ++k) {
      long long idx;
      const std::string_view t = s.token();
      if (t.empty()) s.fail("face " + std::to_string(f) + " has fewer corners than its count " + std::to_string(n) + " (truncated?)");
      if (!s.parse_int(t, idx)) s.fail("face " + std::to_string(f) + " has a non-integer index '" + std::string(t) + "'");
      if (idx < 0 || idx >= nv)
        s.fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(idx) + ", but there are only " + std::to_string(nv) + " vertices");
      corners.push_back(static_cast<int>(idx));
    }
    s.skip_line();  // per-face colours are ignored
    add_polygon(mesh, corners, polygons_split);
  }
  if (coloured) {
    bool unit_range = true;
    for (double x : rgb) unit_range = unit_range && x <= 1.0;
    const char* names[3] = {"red", "green", "blue"};
    for (int c = 0; c < 3; ++c) {
      VertexProperty p{names[c], ScalarType::uint8, {}};
      p.values.resize(static_cast<std::size_t>(nv));
      for (long long v = 0; v < nv; ++v) {
        const double x = rgb[3 * v + c];
        p.values[v] = std::clamp(std::round(unit_range ? x * 255.0 : x), 0.0, 255.0);
      }
      mesh.vertex_properties.push_back(std::move(p));
    }
  }
  if (polygons_split > 0)
    warnings.push_back(file + ": " + std::to_string(polygons_split) + " polygons with more than 3 corners were fan-triangulated");
  return mesh;
}

void write_off(const Mesh& mesh, const ByteSink& sink) {
  const ColourView colours = find_colours(mesh);
  std::string out = colours ? "COFF\n" : "OFF\n";
  append_int(out, static_cast<long long>(mesh.num_vertices()));
  out += ' ';
  append_int(out, static_cast<long long>(mesh.num_faces()));
  out += " 0\n";
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    for (int c = 0; c < 3; ++c) {
      append_double(out, mesh.positions[v][c]);
      out += c < 2 ? ' ' : (colours ? ' ' : '\n');
    }
    if (colours) {
      append_int(out, static_cast<long long>(colours.r->values[v]));
      out += ' ';
      append_int(out, static_cast<long long>(colours.g->values[v]));
      out += ' ';
      append_int(out, static_cast<long long>(colours.b->values[v]));
      out += '\n';
    }
    flush_if_full(out, sink);
  }
  append_counted_faces(out, mesh.faces, sink);
  sink(out);
}

}  // namespace scanmesh::detail
