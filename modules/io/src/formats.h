#pragma once
// Per-format readers and writers behind read_mesh / encode_mesh.
#include <string>
#include <string_view>
#include <vector>

#include "scanmesh/atomic_file.h"
#include "scanmesh/mesh.h"
#include "scanmesh/mesh_io.h"

namespace scanmesh::detail {

Mesh read_obj(std::string_view data, const std::string& file, std::vector<std::string>& warnings);
Mesh read_off(std::string_view data, const std::string& file, std::vector<std::string>& warnings);
Mesh read_ply(std::string_view data, const std::string& file, std::vector<std::string>& warnings,
              bool require_faces = true, RangeGrid* grid = nullptr);
Mesh read_stl(std::string_view data, const std::string& file, std::vector<std::string>& warnings);

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
