#include "scanmesh/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "formats.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/errors.h"

namespace scanmesh {
namespace detail {

void add_polygon(Mesh& mesh, const std::vector<int>& corners, std::size_t& polygons_split) {
  if (corners.size() > 3) ++polygons_split;
  for (std::size_t k = 1; k + 1 < corners.size(); ++k)
    mesh.faces.push_back({corners[0], corners[k], corners[k + 1]});
}

ColourView find_colours(const Mesh& mesh) {
  ColourView c;
  c.r = mesh.find_property("red");
  c.g = mesh.find_property("green");
  c.b = mesh.find_property("blue");
  return c;
}

}  // namespace detail

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

bool is_mesh_extension(const std::string& ext) {
  return ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl";
}

namespace {

// What every mesh read passes: indices in range, finite coordinates, at least one face. A face that
// names one vertex twice (a collapsed triangle, common in welded STL and in decimated meshes) is kept,
// since dropping it could open the surface, but said: it has no area and no normal.
Mesh checked(Mesh mesh, const std::string& path, std::vector<std::string>& warnings) {
  validate_mesh(mesh, "'" + path + "'");
  if (mesh.faces.empty()) throw InputError("'" + path + "': contains no faces");
  std::size_t repeated = 0, first = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Face& t = mesh.faces[f];
    if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) continue;
    if (repeated++ == 0) first = f;
  }
  if (repeated > 0) {
    const Face& t = mesh.faces[first];
    warnings.push_back(path + ": " + std::to_string(repeated) + (repeated == 1 ? " face names" : " faces name") +
                       " a vertex twice (first: face " + std::to_string(first) + ", vertices " + std::to_string(t[0]) + " " +
                       std::to_string(t[1]) + " " + std::to_string(t[2]) +
                       "); kept as they are, without area or normal (the pipeline's mesh.cleanup removes them)");
  }
  return mesh;
}

}  // namespace

Mesh read_mesh(const std::string& path, std::vector<std::string>* warnings) {
  const std::string ext = lower_extension(path);
  if (!is_mesh_extension(ext))
    throw InputError("'" + path + "': unknown mesh format '" + (ext.empty() ? std::string("(no extension)") : ext) +
                     "'; supported: .obj .off .ply .stl");
  // A big file is read in chunks rather than held whole next to the mesh.
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec) && std::filesystem::file_size(path, ec) > detail::kWholeFileLimit && !ec) {
    std::vector<std::string> local;
    std::vector<std::string>& w = warnings != nullptr ? *warnings : local;
    if (ext == ".ply") return checked(detail::read_ply_file(path, w), path, w);
    if (ext == ".stl") return checked(detail::read_stl_file(path, w), path, w);
    return checked(ext == ".obj" ? detail::read_obj_file(path, w) : detail::read_off_file(path, w), path, w);
  }
  return decode_mesh(read_file(path), path, warnings);
}

Mesh decode_mesh(std::string_view data, const std::string& path, std::vector<std::string>* warnings) {
  const std::string ext = lower_extension(path);
  if (data.empty()) throw InputError("'" + path + "': file is empty");
  std::vector<std::string> local;
  std::vector<std::string>& w = warnings != nullptr ? *warnings : local;
  Mesh mesh;
  if (ext == ".obj") mesh = detail::read_obj(data, path, w);
  else if (ext == ".off") mesh = detail::read_off(data, path, w);
  else if (ext == ".ply") mesh = detail::read_ply(data, path, w);
  else if (ext == ".stl") mesh = detail::read_stl(data, path, w);
  else throw InputError("'" + path + "': unknown mesh format '" + ext + "'; supported: .obj .off .ply .stl");
  return checked(std::move(mesh), path, w);
}

Mesh decode_ply_points(std::string_view data, const std::string& file, std::vector<std::string>* warnings, RangeGrid* grid) {
  if (data.empty()) throw InputError("'" + file + "': file is empty");
  std::vector<std::string> local;
  Mesh mesh = detail::read_ply(data, file, warnings != nullptr ? *warnings : local, false, grid);
  if (mesh.positions.empty()) throw InputError("'" + file + "': contains no vertices");
  return mesh;
}

Mesh read_ply_points(const std::string& path, std::vector<std::string>* warnings) {
  return decode_ply_points(read_file(path), path, warnings);
}

void encode_mesh(const Mesh& mesh, const std::string& extension, const WriteOptions& options, const ByteSink& sink) {
  if (extension == ".obj") return detail::write_obj(mesh, sink);
  if (extension == ".off") return detail::write_off(mesh, sink);
  if (extension == ".ply") return detail::write_ply(mesh, options.binary, sink);
  if (extension == ".stl") return detail::write_stl(mesh, options.binary, sink);
  throw UsageError("unknown mesh format '" + extension + "'; supported: .obj .off .ply .stl");
}

std::string encode_mesh(const Mesh& mesh, const std::string& extension, const WriteOptions& options) {
  std::string out;
  encode_mesh(mesh, extension, options, [&out](std::string_view piece) { out += piece; });
  return out;
}

void write_mesh(const Mesh& mesh, const std::string& path, const WriteOptions& options) {
  const std::string ext = lower_extension(path);
  if (!is_mesh_extension(ext))
    throw UsageError("output '" + path + "': unknown mesh format '" + (ext.empty() ? std::string("(no extension)") : ext) +
                     "'; supported: .obj .off .ply .stl");
  write_file_atomically(path, [&](const ByteSink& sink) { encode_mesh(mesh, ext, options, sink); });
}

}  // namespace scanmesh
