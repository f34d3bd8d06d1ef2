// Wavefront OBJ: "v x y z [r g b]" and "f a[/t[/n]] b c ..." (1-based, negative = relative).
// Texture coordinates, per-corner normals, groups and materials are not kept.
#include <algorithm>
#include <cmath>

#include "formats.h"
#include "text_scanner.h"

namespace scanmesh::detail {

Mesh read_obj(std::string_view data, const std::string& file, std::vector<std::string>& warnings) {
  Mesh mesh;
  TextScanner s(data, file);
  std::vector<double> colours;  // r,g,b per vertex, only while every vertex has them
  bool all_coloured = true;
  std::size_t polygons_split = 0;
  bool ignored_attributes = false;
  std::vector<int> corners;
  while (!s.at_end()) {
    s.skip_space(true);
    if (s.at_end()) break;
    const std::string_view key = s.token();
    if (key == "v") {
      double xyz[3];
      const std::string what = "vertex " + std::to_string(mesh.positions.size() + 1);
      for (double& c : xyz) c = s.finite_number(s.token(), what);
      mesh.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
      if (s.at_line_end()) {
        all_coloured = false;
      } else {
        double rgb[3];
        bool ok = true;
        for (double& c : rgb) ok = ok && s.parse_double(s.token(), c);
        if (!ok) all_coloured = false;
        else if (all_coloured) colours.insert(colours.end(), rgb, rgb + 3);
      }
    } else if (key == "f") {
      corners.clear();
      while (!s.at_line_end()) {
        std::string_view tok = s.token();
        const auto slash = tok.find('/');
        if (slash != std::string_view::npos) tok = tok.substr(0, slash);
        long long idx = 0;
        if (!s.parse_int(tok, idx) || idx == 0) s.fail("face has an invalid vertex index '" + std::string(tok) + "'");
        const long long n = static_cast<long long>(mesh.positions.size());
        const long long zero_based = idx > 0 ? idx - 1 : n + idx;
        if (zero_based < 0 || zero_based >= n)
          s.fail("face refers to vertex " + std::to_string(idx) + ", but only " + std::to_string(n) +
                 " vertices are defined before it");
        corners.push_back(static_cast<int>(zero_based));
      }
      if (corners.size() < 3) s.fail("face has fewer than three vertices (is the file truncated?)");
      add_polygon(mesh, corners, polygons_split);
    } else if (key == "vt" || key == "vn") {
      ignored_attributes = true;
    }
    s.skip_line();
  }
  if (all_coloured && !mesh.positions.empty() && colours.size() == 3 * mesh.positions.size()) {
    const char* names[3] = {"red", "green", "blue"};
    for (int c = 0; c < 3; ++c) {
      VertexProperty p{names[c], ScalarType::uint8, {}};
      p.values.resize(mesh.positions.size());
      for (std::size_t v = 0; v < mesh.positions.size(); ++v)
        p.values[v] = std::round(std::clamp(colours[3 * v + c], 0.0, 1.0) * 255.0);
      mesh.vertex_properties.push_back(std::move(p));
    }
  }
  if (polygons_split > 0)
    warnings.push_back(file + ": " + std::to_string(polygons_split) + " polygons with more than 3 corners were fan-triangulated");
  if (ignored_attributes)
    warnings.push_back(file + ": texture coordinates and per-corner normals (vt/vn) are not kept");
  return mesh;
}

void write_obj(const Mesh& mesh, const ByteSink& sink) {
  std::string out = "# scanmesh: ";
  append_int(out, static_cast<long long>(mesh.num_vertices()));
  out += " vertices, ";
  append_int(out, static_cast<long long>(mesh.num_faces()));
  out += " faces\n";
  const ColourView colours = find_colours(mesh);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    out += "v ";
    for (int c = 0; c < 3; ++c) {
      append_double(out, mesh.positions[v][c]);
      out += c < 2 ? ' ' : (colours ? ' ' : '\n');
    }
    if (colours) {
      append_double(out, colours.r->values[v] / 255.0);
      out += ' ';
      append_double(out, colours.g->values[v] / 255.0);
      out += ' ';
      append_double(out, colours.b->values[v] / 255.0);
      out += '\n';
    }
    flush_if_full(out, sink);
  }
  for (const Face& f : mesh.faces) {
    out += "f ";
    for (int k = 0; k < 3; ++k) {
      append_int(out, f[k] + 1);
      out += k < 2 ? ' ' : '\n';
    }
    flush_if_full(out, sink);
  }
  sink(out);
}

}  // namespace scanmesh::detail
