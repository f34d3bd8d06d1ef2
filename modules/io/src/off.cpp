// Object File Format: "OFF" (or "COFF" with per-vertex colours), counts, vertices, polygons.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>

#include "file_chunks.h"
#include "formats.h"
#include "text_scanner.h"

namespace scanmesh::detail {

namespace {

// The OFF reader's state across blocks of whole lines: the whole file in one block when it is in memory,
// a few megabytes of lines at a time from disk. A vertex's coordinates may run over several lines, so a
// block can end inside one; the parser then goes on where it stopped when the next block comes.
class OffParser {
 public:
  OffParser(const std::string& file, std::uintmax_t file_size, std::vector<std::string>& warnings)
      : file_(file), file_size_(file_size), warnings_(warnings) {}

  // Parses `block`, whose first line is line `line` of the file; `last`: no block follows. Returns the
  // line after the block.
  std::size_t parse(std::string_view block, std::size_t line, bool last) {
    TextScanner s(block, file_, line);
    // The next token, crossing lines; empty when the block has run out (and more may follow).
    std::string_view tok;
    auto next = [&] { return !(tok = s.any_token(true)).empty() || last; };
    while (phase_ != Phase::done) {
      if (phase_ == Phase::magic) {
        if (!next()) return s.line();
        if (tok == "OFF" || tok == "COFF" || tok == "NOFF" || tok == "CNOFF" || tok == "NCOFF") {
          coloured_ = tok.find('C') != std::string_view::npos;
          if (tok.find('N') != std::string_view::npos) s.fail("OFF with per-vertex normals (" + std::string(tok) + ") is not supported");
        } else if (tok.size() > 3 && tok.substr(0, 3) == "OFF") {
          s.fail("unsupported OFF variant '" + std::string(tok) + "'");
        } else {
          // The header keyword is optional in some writers; the first token must then be the vertex count.
          long long probe;
          if (!s.parse_int(tok, probe)) s.fail("not an OFF file: expected 'OFF' header, found '" + std::string(tok.substr(0, 20)) + "'");
          if (!s.parse_int(tok, counts_[0]) || counts_[0] < 0) s.fail("expected vertex, face and edge counts after the OFF header");
          counted_ = 1;
        }
        phase_ = Phase::counts;
      } else if (phase_ == Phase::counts) {
        for (; counted_ < 3; ++counted_) {
          if (!next()) return s.line();
          if (!s.parse_int(tok, counts_[counted_]) || counts_[counted_] < 0)
            s.fail("expected vertex, face and edge counts after the OFF header");
        }
        const long long nv = counts_[0], nf = counts_[1];
        if (static_cast<std::uintmax_t>(nv) > file_size_ || static_cast<std::uintmax_t>(nf) > file_size_)
          s.fail("vertex/face counts (" + std::to_string(nv) + ", " + std::to_string(nf) + ") are larger than the file could hold");
        mesh_.positions.resize(static_cast<std::size_t>(nv));
        // Room for the faces as counted, as far as the file can hold them (a face line takes at least 8 bytes).
        mesh_.faces.reserve(static_cast<std::size_t>(std::min<std::uintmax_t>(static_cast<std::uintmax_t>(nf), file_size_ / 8)));
        phase_ = Phase::vertices;
      } else if (phase_ == Phase::vertices) {
        const long long nv = counts_[0];
        for (; vertex_ < nv; ++vertex_, coordinate_ = 0) {
          for (; coordinate_ < 3; ++coordinate_) {
            if (!next()) return s.line();
            if (tok.empty()) s.fail("file ends after " + std::to_string(vertex_) + " of " + std::to_string(nv) + " vertices (truncated?)");
            mesh_.positions[vertex_][coordinate_] = s.finite_number(tok, "vertex " + std::to_string(vertex_));
          }
          if (coloured_) {  // on the line of the last coordinate, which the block holds whole
            for (int c = 0; c < 3; ++c) {
              double x;
              if (!s.parse_double(s.token(), x)) s.fail("COFF vertex " + std::to_string(vertex_) + " needs a colour");
              rgb_.push_back(x);
            }
          }
          s.skip_line();
        }
        phase_ = Phase::faces;
      } else {
        const long long nv = counts_[0], nf = counts_[1];
        for (; face_ < nf; ++face_) {
          if (!next()) return s.line();
          long long n = 0;
          if (tok.empty()) s.fail("file ends after " + std::to_string(face_) + " of " + std::to_string(nf) + " faces (truncated?)");
          if (!s.parse_int(tok, n) || n < 3)
            s.fail("face " + std::to_string(face_) + " must start with a corner count >= 3, found '" + std::string(tok) + "'");
          corners_.clear();
          for (long long k = 0; k < n; ++k) {  // a face's line is in the block whole
            long long idx;
            const std::string_view t = s.token();
            if (t.empty()) s.fail("face " + std::to_string(face_) + " has fewer corners than its count " + std::to_string(n) + " (truncated?)");
            if (!s.parse_int(t, idx)) s.fail("face " + std::to_string(face_) + " has a non-integer index '" + std::string(t) + "'");
            if (idx < 0 || idx >= nv)
              s.fail("face " + std::to_string(face_) + " refers to vertex " + std::to_string(idx) + ", but there are only " + std::to_string(nv) + " vertices");
            corners_.push_back(static_cast<int>(idx));
          }
          s.skip_line();  // per-face colours are ignored
          add_polygon(mesh_, corners_, polygons_split_);
        }
        phase_ = Phase::done;
      }
    }
    return s.line();
  }

  Mesh finish() {
    if (coloured_) {
      const std::size_t nv = mesh_.positions.size();
      bool unit_range = true;
      for (double x : rgb_) unit_range = unit_range && x <= 1.0;
      const char* names[3] = {"red", "green", "blue"};
      for (int c = 0; c < 3; ++c) {
        VertexProperty p{names[c], ScalarType::uint8, {}};
        p.values.resize(nv);
        for (std::size_t v = 0; v < nv; ++v) {
          const double x = rgb_[3 * v + c];
          p.values[v] = std::clamp(std::round(unit_range ? x * 255.0 : x), 0.0, 255.0);
        }
        mesh_.vertex_properties.push_back(std::move(p));
      }
    }
    if (polygons_split_ > 0)
      warnings_.push_back(file_ + ": " + std::to_string(polygons_split_) + " polygons with more than 3 corners were fan-triangulated");
    return std::move(mesh_);
  }

 private:
  enum class Phase { magic, counts, vertices, faces, done };
  const std::string& file_;
  std::uintmax_t file_size_;
  std::vector<std::string>& warnings_;
  Phase phase_ = Phase::magic;
  bool coloured_ = false;
  long long counts_[3] = {0, 0, 0};
  int counted_ = 0;
  long long vertex_ = 0, face_ = 0;
  int coordinate_ = 0;
  Mesh mesh_;
  std::vector<double> rgb_;
  std::vector<int> corners_;
  std::size_t polygons_split_ = 0;
};

}  // namespace

Mesh read_off(std::string_view data, const std::string& file, std::vector<std::string>& warnings) {
  OffParser parser(file, data.size(), warnings);
  parser.parse(data, 1, true);
  return parser.finish();
}

Mesh read_off_file(const std::string& path, std::vector<std::string>& warnings, std::size_t chunk_bytes) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  OffParser parser(path, ec ? 0 : size, warnings);
  for_each_line_block(path, chunk_bytes, [&](std::string_view block, std::size_t line, bool last) { return parser.parse(block, line, last); });
  return parser.finish();
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
