#pragma once
// Per-format readers and writers behind read_mesh / encode_mesh.
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "scanmesh/atomic_file.h"
#include "scanmesh/mesh.h"
#include "scanmesh/mesh_io.h"

namespace scanmesh::detail {

/// Files up to this size are read whole; bigger ones are read a block of whole lines or a chunk at a time
/// (the *_file readers below), so the file is not held next to what is read from it.
constexpr std::uintmax_t kWholeFileLimit = std::uintmax_t{16} << 20;

Mesh read_obj(std::string_view data, const std::string& file, std::vector<std::string>& warnings);
/// Reads an OBJ file from disk a block of whole lines (about `chunk_bytes`) at a time.
Mesh read_obj_file(const std::string& path, std::vector<std::string>& warnings, std::size_t chunk_bytes = std::size_t{4} << 20);
Mesh read_off(std::string_view data, const std::string& file, std::vector<std::string>& warnings);
/// Reads an OFF file from disk a block of whole lines (about `chunk_bytes`) at a time.
Mesh read_off_file(const std::string& path, std::vector<std::string>& warnings, std::size_t chunk_bytes = std::size_t{4} << 20);
/// More of a PLY file's binary body: called with the number of unread bytes at the end of the current
/// window, returns a new window starting with them (shorter than asked at the end of the file).
using PlyRefill = std::function<std::string_view(std::size_t keep)>;

/// With `refill`, `data` holds the start of the file (at least its header), `file_size` its full size
/// (for the checks of the header's counts), and the body (binary or text) comes through `refill`.
Mesh read_ply(std::string_view data, const std::string& file, std::vector<std::string>& warnings,
              bool require_faces = true, RangeGrid* grid = nullptr, std::size_t file_size = 0,
              const PlyRefill* refill = nullptr);
/// Reads a PLY file from disk; the body is read in chunks of `chunk_bytes` rather than as a whole.
Mesh read_ply_file(const std::string& path, std::vector<std::string>& warnings, bool require_faces = true,
                   RangeGrid* grid = nullptr, std::size_t chunk_bytes = std::size_t{4} << 20);
Mesh read_stl(std::string_view data, const std::string& file, std::vector<std::string>& warnings);
/// Reads an STL file from disk; a binary one a chunk of whole triangle records at a time, a text one whole.
Mesh read_stl_file(const std::string& path, std::vector<std::string>& warnings, std::size_t chunk_bytes = std::size_t{4} << 20);

// Writers hand their file to `sink` in pieces of about a megabyte.
void write_obj(const Mesh& mesh, const ByteSink& sink);
void write_off(const Mesh& mesh, const ByteSink& sink);
void write_ply(const Mesh& mesh, bool binary, const ByteSink& sink);
void write_stl(const Mesh& mesh, bool binary, const ByteSink& sink);

/// Appends fan triangles of a polygon; counts polygons with more than three corners.
void add_polygon(Mesh& mesh, const std::vector<int>& corners, std::size_t& polygons_split);

/// The PLY header name of a scalar type ("float", "uchar", ...).
const char* ply_type_name(ScalarType t);

/// Colour properties (red, green, blue) if all three exist, else nullptrs.
struct ColourView {
  const VertexProperty* r = nullptr;
  const VertexProperty* g = nullptr;
  const VertexProperty* b = nullptr;
  explicit operator bool() const { return r && g && b; }
};
ColourView find_colours(const Mesh& mesh);

}  // namespace scanmesh::detail
