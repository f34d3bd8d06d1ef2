// PLY (Stanford polygon format): ascii, binary_little_endian and binary_big_endian.
// Every scalar vertex property is kept with its type; faces come from the list property
// "vertex_indices" (or "vertex_index"); other elements are skipped with a warning.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "file_chunks.h"
#include "formats.h"
#include "scanmesh/schema.h"
#include "text_scanner.h"

namespace scanmesh::detail {
namespace {

enum class Encoding { ascii, little, big };

bool parse_type(std::string_view name, ScalarType& t) {
  if (name == "char" || name == "int8") t = ScalarType::int8;
  else if (name == "uchar" || name == "uint8") t = ScalarType::uint8;
  else if (name == "short" || name == "int16") t = ScalarType::int16;
  else if (name == "ushort" || name == "uint16") t = ScalarType::uint16;
  else if (name == "int" || name == "int32") t = ScalarType::int32;
  else if (name == "uint" || name == "uint32") t = ScalarType::uint32;
  else if (name == "float" || name == "float32") t = ScalarType::float32;
  else if (name == "double" || name == "float64") t = ScalarType::float64;
  else return false;
  return true;
}

}  // namespace

const char* ply_type_name(ScalarType t) {
  switch (t) {
    case ScalarType::int8: return "char";
    case ScalarType::uint8: return "uchar";
    case ScalarType::int16: return "short";
    case ScalarType::uint16: return "ushort";
    case ScalarType::int32: return "int";
    case ScalarType::uint32: return "uint";
    case ScalarType::float32: return "float";
    case ScalarType::float64: return "double";
  }
  return "double";
}

namespace {

std::size_t type_size(ScalarType t) {
  switch (t) {
    case ScalarType::int8:
    case ScalarType::uint8: return 1;
    case ScalarType::int16:
    case ScalarType::uint16: return 2;
    case ScalarType::int32:
    case ScalarType::uint32:
    case ScalarType::float32: return 4;
    case ScalarType::float64: return 8;
  }
  return 8;
}

struct Property {
  std::string name;
  ScalarType type{};
  bool is_list = false;
  ScalarType count_type{};
};

struct Element {
  std::string name;
  long long count = 0;
  std::vector<Property> properties;
};

template <typename T>
T load(const char* p, bool swap) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if (swap) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    std::memcpy(&v, b, sizeof(T));
  }
  return v;
}

// Reads values from either the text or the binary body of a PLY file, through a window: all of the body
// when the file is in memory, else a chunk at a time (`refill`). A text body is scanned (by `text`, which
// also reports errors with their line numbers) up to the window's last whole line, so no number is cut
// in two; the unfinished line is kept for the next window.
class ValueReader {
 public:
  ValueReader(std::string_view window, const PlyRefill* refill, Encoding enc, TextScanner& text)
      : window_(window), refill_(refill), enc_(enc), text_(text) {
    if (enc_ == Encoding::ascii && refill_ != nullptr) {
      const std::size_t nl = window_.rfind('\n');
      line_end_ = nl == std::string_view::npos ? 0 : nl + 1;
      text_.limit(text_.position() + line_end_);
    }
  }

  double read(ScalarType t, const Element& e, long long item) {
    if (enc_ == Encoding::ascii) {
      std::string_view tok = text_.any_token(false);
      while (tok.empty() && next_lines()) tok = text_.any_token(false);
      if (tok.empty()) text_.fail("file ends while reading " + what(e, item) + " (truncated?)");
      double v = 0.0;
      const auto st = TextScanner::parse_number(tok, v);
      if (st == TextScanner::NumberStatus::out_of_range) text_.fail("value '" + std::string(tok.substr(0, 30)) + "' in " + what(e, item) + " is too large for a double");
      if (st != TextScanner::NumberStatus::ok) text_.fail("non-numeric value '" + std::string(tok.substr(0, 20)) + "' in " + what(e, item));
      return v;
    }
    const std::size_t n = type_size(t);
    if (pos_ + n > window_.size()) {
      if (refill_ != nullptr) {
        window_ = (*refill_)(window_.size() - pos_);
        pos_ = 0;
      }
      if (pos_ + n > window_.size())
        throw InputError(text_.file() + ": binary data ends while reading " + what(e, item) + " (truncated?)");
    }
    const char* p = window_.data() + pos_;
    pos_ += n;
    const bool swap = (enc_ == Encoding::big) == (std::endian::native == std::endian::little);
    switch (t) {
      case ScalarType::int8: return static_cast<double>(load<std::int8_t>(p, false));
      case ScalarType::uint8: return static_cast<double>(load<std::uint8_t>(p, false));
      case ScalarType::int16: return static_cast<double>(load<std::int16_t>(p, swap));
      case ScalarType::uint16: return static_cast<double>(load<std::uint16_t>(p, swap));
      case ScalarType::int32: return static_cast<double>(load<std::int32_t>(p, swap));
      case ScalarType::uint32: return static_cast<double>(load<std::uint32_t>(p, swap));
      case ScalarType::float32: return static_cast<double>(load<float>(p, swap));
      case ScalarType::float64: return load<double>(p, swap);
    }
    return 0.0;
  }

 private:
  static std::string what(const Element& e, long long item) {
    return e.name + " " + std::to_string(item) + " of " + std::to_string(e.count);
  }
  // A streamed text body: the next window's whole lines (with the last window's unfinished line in
  // front) handed to the scanner; false when the file has no more.
  bool next_lines() {
    if (refill_ == nullptr || text_done_) return false;
    std::size_t keep = window_.size() - line_end_;
    for (;;) {
      window_ = (*refill_)(keep);
      if (window_.size() == keep) {  // the end of the file: its last line has no newline
        text_done_ = true;
        line_end_ = window_.size();
        break;
      }
      // Only the new bytes can hold a newline (the kept ones are one unfinished line).
      const std::size_t nl = window_.substr(keep).rfind('\n');
      if (nl != std::string_view::npos) {
        line_end_ = keep + nl + 1;
        break;
      }
      keep = window_.size();  // a line longer than the chunk: read on
    }
    text_.continue_on(window_.substr(0, line_end_));
    return line_end_ > 0;
  }
  std::string_view window_;
  std::size_t pos_ = 0;
  std::size_t line_end_ = 0;  // text body: the window's whole lines end here
  bool text_done_ = false;
  const PlyRefill* refill_;
  Encoding enc_;
  TextScanner& text_;
};

}  // namespace

Mesh read_ply(std::string_view data, const std::string& file, std::vector<std::string>& warnings,
              bool require_faces, RangeGrid* grid, std::size_t file_size, const PlyRefill* refill) {
  if (refill == nullptr) file_size = data.size();
  TextScanner s(data, file);
  if (s.token() != "ply") s.fail("not a PLY file: the first line must be 'ply'");
  s.skip_line();
  Encoding enc = Encoding::ascii;
  bool have_format = false;
  long long grid_cols = -1, grid_rows = -1;
  std::vector<Element> elements;
  for (;;) {
    if (s.at_end()) s.fail("header has no 'end_header' line (truncated?)");
    const std::string_view key = s.token();
    if (key == "format") {
      const std::string_view f = s.token();
      if (f == "ascii") enc = Encoding::ascii;
      else if (f == "binary_little_endian") enc = Encoding::little;
      else if (f == "binary_big_endian") enc = Encoding::big;
      else s.fail("unknown PLY format '" + std::string(f) + "'");
      have_format = true;
    } else if (key == "element") {
      Element e;
      e.name = std::string(s.token());
      if (!s.parse_int(s.token(), e.count) || e.count < 0) s.fail("element '" + e.name + "' needs a non-negative count");
      if (e.count > static_cast<long long>(file_size)) s.fail("element '" + e.name + "' count " + std::to_string(e.count) + " is larger than the file could hold");
      elements.push_back(std::move(e));
    } else if (key == "property") {
      if (elements.empty()) s.fail("property before any element");
      Property p;
      std::string_view t = s.token();
      if (t == "list") {
        p.is_list = true;
        if (!parse_type(s.token(), p.count_type)) s.fail("unknown list count type");
        t = s.token();
      }
      if (!parse_type(t, p.type)) s.fail("unknown property type '" + std::string(t) + "'");
      p.name = std::string(s.token());
      if (p.name.empty()) s.fail("property without a name");
      elements.back().properties.push_back(std::move(p));
    } else if (key == "end_header") {
      s.skip_line();
      break;
    } else if (key == "obj_info") {
      // Stanford range scans give their grid size here ("obj_info num_cols 512").
      const std::string_view name = s.token();
      long long v = 0;
      if ((name == "num_cols" || name == "num_rows") && s.parse_int(s.token(), v)) (name == "num_cols" ? grid_cols : grid_rows) = v;
    } else if (key == "comment" || key.empty()) {
      // ignored
    } else {
      s.fail("unknown header keyword '" + std::string(key.substr(0, 30)) + "'");
    }
    s.skip_line();
  }
  if (!have_format) s.fail("header has no 'format' line");

  // Every element must fit in the bytes after the header before anything is allocated for it: a binary
  // item takes at least the sizes of its scalars and list counts, a text value at least two characters.
  {
    const double remaining = static_cast<double>(file_size - std::min(file_size, s.position()));
    double need = 0.0;
    for (const auto& e : elements) {
      double item = 0.0;
      for (const auto& p : e.properties)
        item += enc == Encoding::ascii ? 2.0 : static_cast<double>(type_size(p.is_list ? p.count_type : p.type));
      need += item * static_cast<double>(e.count);
      if (need > remaining + 2.0)
        throw InputError(file + ": element '" + e.name + "' announces " + std::to_string(e.count) + " items, but the " +
                         std::to_string(static_cast<long long>(remaining)) + " bytes after the header cannot hold them (truncated or corrupt header)");
    }
  }

  Mesh mesh;
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  const Element* strips = nullptr;
  const Element* range = nullptr;
  for (const auto& e : elements) {
    if (e.name == "vertex") vertex = &e;
    if (e.name == "face") face = &e;
    if (e.name == "tristrips") strips = &e;
    if (e.name == "range_grid") range = &e;
  }
  if (vertex == nullptr) s.fail("no 'vertex' element");
  int xyz[3] = {-1, -1, -1};
  for (std::size_t i = 0; i < vertex->properties.size(); ++i) {
    const auto& p = vertex->properties[i];
    if (p.is_list) continue;
    if (p.name == "x") xyz[0] = static_cast<int>(i);
    if (p.name == "y") xyz[1] = static_cast<int>(i);
    if (p.name == "z") xyz[2] = static_cast<int>(i);
  }
  for (int c = 0; c < 3; ++c)
    if (xyz[c] < 0) throw InputError(file + ": vertex element has no '" + std::string(1, "xyz"[c]) + "' property");
  if (face == nullptr && strips == nullptr && require_faces)
    throw InputError(file + ": no 'face' (or 'tristrips') element (a point cloud, not a mesh?)");
  // The list of vertex indices of a face / strip / range-grid element.
  auto index_list = [&](const Element* e) {
    int list = -1;
    if (e != nullptr)
      for (std::size_t i = 0; i < e->properties.size(); ++i) {
        const auto& p = e->properties[i];
        if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) list = static_cast<int>(i);
      }
    if (e != nullptr && list < 0) throw InputError(file + ": " + e->name + " element has no 'vertex_indices' list");
    return list;
  };
  const int face_list = index_list(face), strip_list = index_list(strips), range_list = index_list(range);
  if (range != nullptr && grid != nullptr) {
    if (grid_cols <= 0 || grid_rows <= 0)
      throw InputError(file + ": range_grid element without 'obj_info num_cols' and 'num_rows' in the header");
    if (static_cast<double>(grid_cols) * static_cast<double>(grid_rows) != static_cast<double>(range->count))
      throw InputError(file + ": range_grid has " + std::to_string(range->count) + " cells, but num_cols x num_rows = " +
                       std::to_string(grid_cols) + " x " + std::to_string(grid_rows));
    grid->cols = static_cast<int>(grid_cols);
    grid->rows = static_cast<int>(grid_rows);
    grid->cells.assign(static_cast<std::size_t>(range->count), -1);
  }

  // Vertex properties other than x/y/z are kept.
  std::vector<int> prop_slot(vertex->properties.size(), -1);
  for (std::size_t i = 0; i < vertex->properties.size(); ++i) {
    const auto& p = vertex->properties[i];
    if (p.is_list || static_cast<int>(i) == xyz[0] || static_cast<int>(i) == xyz[1] || static_cast<int>(i) == xyz[2]) continue;
    prop_slot[i] = static_cast<int>(mesh.vertex_properties.size());
    mesh.vertex_properties.push_back({p.name, p.type, {}});
  }
  for (auto& vp : mesh.vertex_properties) vp.values.resize(static_cast<std::size_t>(vertex->count));
  mesh.positions.resize(static_cast<std::size_t>(vertex->count));
  // A triangle mesh's faces fill the table exactly (grown face by face it held up to twice that through the
  // whole run: 12.6 MB for 9.7 on 810k faces). The count fits the file (checked above).
  if (face != nullptr) mesh.faces.reserve(static_cast<std::size_t>(face->count));

  ValueReader r(data.substr(std::min(data.size(), s.position())), refill, enc, s);
  std::size_t polygons_split = 0, strip_degenerate = 0;
  std::vector<int> corners;
  auto vertex_index = [&](const Element& e, long long item, double idx, bool allow_minus_one) {
    if (allow_minus_one && idx == -1.0) return -1;
    if (!(idx >= 0) || idx >= static_cast<double>(vertex->count) || idx != std::floor(idx))
      throw InputError(file + ": " + e.name + " " + std::to_string(item) + " refers to vertex " + format_number(idx) +
                       ", but there are only " + std::to_string(vertex->count) + " vertices");
    return static_cast<int>(idx);
  };
  for (const auto& e : elements) {
    const bool is_vertex = &e == vertex;
    const int list_of_interest = &e == face ? face_list : &e == strips ? strip_list : &e == range && grid ? range_list : -1;
    if (!is_vertex && list_of_interest < 0) warnings.push_back(file + ": element '" + e.name + "' is not kept");
    for (long long item = 0; item < e.count; ++item) {
      for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
        const Property& p = e.properties[pi];
        if (p.is_list) {
          const double n = r.read(p.count_type, e, item);
          const double max_len = &e == strips ? 1e9 : 1e6;
          if (!(n >= 0) || n > max_len || n != std::floor(n))
            throw InputError(file + ": " + e.name + " " + std::to_string(item) + " has an invalid list length");
          const auto len = static_cast<long long>(n);
          if (static_cast<int>(pi) != list_of_interest) {
            for (long long k = 0; k < len; ++k) r.read(p.type, e, item);
          } else if (&e == face) {
            corners.clear();
            for (long long k = 0; k < len; ++k) corners.push_back(vertex_index(e, item, r.read(p.type, e, item), false));
            if (corners.size() < 3) throw InputError(file + ": face " + std::to_string(item) + " has fewer than three vertices");
            add_polygon(mesh, corners, polygons_split);
          } else if (&e == strips) {
            // Triangle strips, restarted by -1: triangle k of a strip is (s_k, s_k+1, s_k+2), every other one
            // reversed so all keep the strip's orientation. Degenerate joins (a repeated vertex) are dropped.
            corners.clear();
            for (long long k = 0; k <= len; ++k) {
              const int v = k < len ? vertex_index(e, item, r.read(p.type, e, item), true) : -1;
              if (v >= 0) {
                corners.push_back(v);
                if (corners.size() < 3) continue;
                const std::size_t t = corners.size() - 3;
                Face f = {corners[t], corners[t + 1], corners[t + 2]};
                if (t % 2 == 1) std::swap(f[0], f[1]);
                if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) ++strip_degenerate;
                else mesh.faces.push_back(f);
              } else {
                corners.clear();
              }
            }
          } else {  // range grid cell: no index (nothing seen) or one vertex
            if (len > 1) throw InputError(file + ": range_grid cell " + std::to_string(item) + " lists " + std::to_string(len) + " vertices (at most 1)");
            if (len == 1) grid->cells[static_cast<std::size_t>(item)] = vertex_index(e, item, r.read(p.type, e, item), false);
          }
        } else {
          const double v = r.read(p.type, e, item);
          if (is_vertex) {
            if (static_cast<int>(pi) == xyz[0]) mesh.positions[item][0] = v;
            else if (static_cast<int>(pi) == xyz[1]) mesh.positions[item][1] = v;
            else if (static_cast<int>(pi) == xyz[2]) mesh.positions[item][2] = v;
            else if (prop_slot[pi] >= 0) mesh.vertex_properties[prop_slot[pi]].values[item] = v;
          }
        }
      }
    }
  }
  if (polygons_split > 0)
    warnings.push_back(file + ": " + std::to_string(polygons_split) + " polygons with more than 3 corners were fan-triangulated");
  if (strip_degenerate > 0)
    warnings.push_back(file + ": " + std::to_string(strip_degenerate) + " degenerate triangles joining triangle strips were dropped");
  return mesh;
}

}  // namespace scanmesh::detail

namespace scanmesh::detail {

Mesh read_ply_file(const std::string& path, std::vector<std::string>& warnings, bool require_faces, RangeGrid* grid,
                   std::size_t chunk_bytes) {
  auto whole = [&] { return read_ply(read_file(path), path, warnings, require_faces, grid); };
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return whole();  // read_file names the problem
  const auto size = static_cast<std::size_t>(std::filesystem::file_size(path, ec));
  if (ec) return whole();
  FileChunks chunks(path, chunk_bytes);
  // The start of the file, read until it holds the whole header (else the file is read whole, and the
  // reader says what is wrong with it). Only the new bytes, and the few before them, are searched.
  constexpr std::size_t kMaxHeader = std::size_t{16} << 20;
  const std::string_view mark = "end_header";
  std::string_view window = chunks.next(0);
  while (window.find(mark, window.size() - std::min(window.size(), chunks.fresh() + mark.size())) == std::string_view::npos) {
    if (chunks.fresh() == 0 || window.size() >= kMaxHeader) return whole();
    window = chunks.next(window.size());
  }
  const PlyRefill refill = [&](std::size_t keep) { return chunks.next(keep); };
  return read_ply(window, path, warnings, require_faces, grid, size, &refill);
}

}  // namespace scanmesh::detail
