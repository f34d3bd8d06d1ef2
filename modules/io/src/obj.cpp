// Wavefront OBJ: "v x y z [r g b]" and "f a[/t[/n]] b c ..." (1-based, negative = relative).
// Texture coordinates, per-corner normals, groups and materials are not kept.
#include <algorithm>
#include <cmath>

#include "file_chunks.h"
#include "formats.h"
#include "text_scanner.h"

namespace scanmesh::detail {

namespace {

// The OBJ reader's state across blocks of whole lines: a file is parsed in one block when it is in
// memory, or a few megabytes of lines at a time from disk. Every statement lies on one line, so the
// blocks give what one pass over the whole text gives.
class ObjParser {
 public:
  ObjParser(const std::string& file, std::vector<std::string>& warnings) : file_(file), warnings_(warnings) {}

  // Parses `block` (whole lines), whose first line is line `line` of the file; returns the line after it.
  std::size_t parse(std::string_view block, std::size_t line) {
    TextScanner s(block, file_, line);
    while (!s.at_end()) {
      s.skip_space(true);
      if (s.at_end()) break;
      const std::string_view key = s.token();
      if (key == "v") {
        double xyz[3];
        const std::string what = "vertex " + std::to_string(mesh_.positions.size() + 1);
        for (double& c : xyz) c = s.finite_number(s.token(), what);
        mesh_.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
        if (s.at_line_end()) {
          all_coloured_ = false;
        } else {
          double rgb[3];
          bool ok = true;
          for (double& c : rgb) ok = ok && s.parse_double(s.token(), c);
          if (!ok) all_coloured_ = false;
          else if (all_coloured_) colours_.insert(colours_.end(), rgb, rgb + 3);
        }
      } else if (key == "f") {
        corners_.clear();
        while (!s.at_line_end()) {
          std::string_view tok = s.token();
          const auto slash = tok.find('/');
          if (slash != std::string_view::npos) tok = tok.substr(0, slash);
          long long idx = 0;
          if (!s.parse_int(tok, idx) || idx == 0) s.fail("face has an invalid vertex index '" + std::string(tok) + "'");
          const long long n = static_cast<long long>(mesh_.positions.size());
          const long long zero_based = idx > 0 ? idx - 1 : n + idx;
          if (zero_based < 0 || zero_based >= n)
            s.fail("face refers to vertex " + std::to_string(idx) + ", but only " + std::to_string(n) +
                   " vertices are defined before it");
          corners_.push_back(static_cast<int>(zero_based));
        }
        if (corners_.size() < 3) s.fail("face has fewer than three vertices (is the file truncated?)");
        add_polygon(mesh_, corners_, polygons_split_);
      } else if (key == "vt" || key == "vn") {
        ignored_attributes_ = true;
      }
      s.skip_line();
    }
    return s.line();
  }

  Mesh finish() {
    if (all_coloured_ && !mesh_.positions.empty() && colours_.size() == 3 * mesh_.positions.size()) {
      const char* names[3] = {"red", "green", "blue"};
      for (int c = 0; c < 3; ++c) {
        VertexProperty p{names[c], ScalarType::uint8, {}};
        p.values.resize(mesh_.positions.size());
        for (std::size_t v = 0; v < mesh_.positions.size(); ++v)
          p.values[v] = std::round(std::clamp(colours_[3 * v + c], 0.0, 1.0) * 255.0);
        mesh_.vertex_properties.push_back(std::move(p));
      }
    }
    if (polygons_split_ > 0)
      warnings_.push_back(file_ + ": " + std::to_string(polygons_split_) + " polygons with more than 3 corners were fan-triangulated");
    if (ignored_attributes_)
      warnings_.push_back(file_ + ": texture coordinates and per-corner normals (vt/vn) are not kept");
    return std::move(mesh_);
  }

 private:
  const std::string& file_;
  std::vector<std::string>& warnings_;
  Mesh mesh_;
  std::vector<double> colours_;  // r,g,b per vertex, only while every vertex has them
  bool all_coloured_ = true;
  std::size_t polygons_split_ = 0;
  bool ignored_attributes_ = false;
  std::vector<int> corners_;
};

}  // namespace

Mesh read_obj(std::string_view data, const std::string& file, std::vector<std::string>& warnings) {
  ObjParser parser(file, warnings);
  parser.parse(data, 1);
  return parser.finish();
}

Mesh read_obj_file(const std::string& path, std::vector<std::string>& warnings, std::size_t chunk_bytes) {
  ObjParser parser(path, warnings);
  for_each_line_block(path, chunk_bytes, [&](std::string_view block, std::size_t line, bool) { return parser.parse(block, line); });
  return parser.finish();
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
