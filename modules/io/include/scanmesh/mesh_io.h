#pragma once
// Reading and writing triangle meshes: OBJ, OFF, PLY (ascii, binary little/big endian) and STL (ascii,
// binary). The format is chosen by the file extension (case-insensitive).
//
// What is kept: vertex order (never changed), faces in file order (polygons are fan-triangulated,
// which is reported as a warning), and per-vertex properties: PLY keeps every scalar vertex property
// with its type (normals nx/ny/nz, colours red/green/blue/alpha, scanner values, ...), OBJ keeps
// "v x y z r g b" colours, OFF keeps COFF colours. STL has no shared vertices: identical corner
// coordinates are welded into one vertex, in order of first appearance.
#include <string>
#include <string_view>
#include <vector>

#include "scanmesh/atomic_file.h"
#include "scanmesh/mesh.h"

namespace scanmesh {

/// Reads a mesh. Throws InputError with a message naming the file and the problem (missing, empty,
/// truncated, malformed, NaN coordinates, index out of range, unknown extension). Non-fatal oddities
/// (polygons triangulated, ignored elements) are appended to `warnings` if given.
Mesh read_mesh(const std::string& path, std::vector<std::string>* warnings = nullptr);

/// The same on a file's bytes in memory; `file` names it in messages and its extension picks the format.
Mesh decode_mesh(std::string_view data, const std::string& file, std::vector<std::string>* warnings = nullptr);

/// The range image of a Stanford range scan PLY (`element range_grid` with `obj_info num_cols/num_rows`):
/// for every grid cell, row by row, the index of the vertex measured there, or -1.
struct RangeGrid {
  int cols = 0, rows = 0;
  std::vector<int> cells;
};

/// Reads the vertices (with all their properties) and, if present, the faces of a PLY file: for point
/// clouds stored as PLY. Throws InputError like read_mesh (but a file without faces is fine).
Mesh read_ply_points(const std::string& path, std::vector<std::string>* warnings = nullptr);
/// The same on a PLY file's bytes already in memory; `file` names it in messages. With `grid`, a
/// `range_grid` element is read into it (cols = 0 if the file has none).
Mesh decode_ply_points(std::string_view data, const std::string& file, std::vector<std::string>* warnings = nullptr,
                       RangeGrid* grid = nullptr);

/// How a mesh is encoded on disk.
struct WriteOptions {
  bool binary = true;  ///< PLY and STL: binary (exact, compact) or ascii. OBJ and OFF are always text.
};

/// Writes a mesh atomically (temporary file + rename). Text formats print coordinates with the shortest
/// representation that reads back to the same double, so a write/read round trip is exact.
/// Throws UsageError for an unknown extension, OutputError if the file cannot be written.
void write_mesh(const Mesh& mesh, const std::string& path, const WriteOptions& options = {});

/// Serialises a mesh into memory in the format given by `extension` (".ply", ".obj", ...).
std::string encode_mesh(const Mesh& mesh, const std::string& extension, const WriteOptions& options = {});
/// The same bytes handed to `sink` in pieces of about a megabyte (what write_mesh streams to its file).
void encode_mesh(const Mesh& mesh, const std::string& extension, const WriteOptions& options, const ByteSink& sink);

/// Lower-case extension of a path including the dot (".ply"), or "" if none.
std::string lower_extension(const std::string& path);

/// True if read_mesh understands this extension.
bool is_mesh_extension(const std::string& extension);

}  // namespace scanmesh
