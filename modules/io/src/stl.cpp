// STL, ascii and binary. STL stores three corner coordinates per triangle; identical coordinates are
// welded into one vertex (first appearance decides the order) so the mesh has connectivity.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <unordered_map>

#include "file_chunks.h"
#include "formats.h"
#include "text_scanner.h"

namespace scanmesh::detail {
namespace {

struct PointHash {
  std::size_t operator()(const Vec3& p) const {
    std::size_t h = 1469598103934665603ull;
    for (int c = 0; c < 3; ++c) {
      std::uint64_t bits;
      const double v = p[c] == 0.0 ? 0.0 : p[c];  // -0 and +0 weld together
      std::memcpy(&bits, &v, 8);
      h = (h ^ bits) * 1099511628211ull;
    }
    return h;
  }
};

class Welder {
 public:
  explicit Welder(Mesh& mesh) : mesh_(mesh) {}
  int add(const Vec3& p) {
    const Vec3 key(p[0] == 0.0 ? 0.0 : p[0], p[1] == 0.0 ? 0.0 : p[1], p[2] == 0.0 ? 0.0 : p[2]);
    auto [it, inserted] = index_.try_emplace(key, static_cast<int>(mesh_.positions.size()));
    if (inserted) mesh_.positions.push_back(p);
    return it->second;
  }

 private:
  Mesh& mesh_;
  std::unordered_map<Vec3, int, PointHash> index_;
};

// Adds the triangles of whole 50-byte binary records (normal, three corners, attribute bytes).
void add_binary_records(std::string_view records, Welder& weld, Mesh& mesh) {
  for (std::size_t at = 0; at + 50 <= records.size(); at += 50) {
    const char* p = records.data() + at + 12;
    Face f;
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      std::memcpy(xyz, p + 12 * k, 12);
      f[k] = weld.add(Vec3(xyz[0], xyz[1], xyz[2]));
    }
    mesh.faces.push_back(f);
  }
}

Mesh read_binary_stl(std::string_view data, std::uint32_t n) {
  Mesh mesh;
  Welder weld(mesh);
  mesh.faces.reserve(n);
  add_binary_records(data.substr(84, 50 * static_cast<std::size_t>(n)), weld, mesh);
  return mesh;
}

Mesh read_ascii_stl(std::string_view data, const std::string& file) {
  Mesh mesh;
  Welder weld(mesh);
  TextScanner s(data, file);
  if (s.any_token(false) != "solid") s.fail("not an STL file");
  s.skip_line();
  Face f{};
  int corner = 0;
  bool ended = false;
  while (!s.at_end()) {
    const std::string_view key = s.any_token(false);
    if (key.empty()) break;
    if (key == "vertex") {
      double xyz[3];
      for (double& c : xyz) c = s.finite_number(s.token(), "vertex of facet " + std::to_string(mesh.faces.size() + 1));
      if (corner >= 3) s.fail("facet with more than three vertices");
      f[corner++] = weld.add(Vec3(xyz[0], xyz[1], xyz[2]));
    } else if (key == "endloop") {
      if (corner != 3) s.fail("facet with " + std::to_string(corner) + " vertices; STL facets are triangles");
      mesh.faces.push_back(f);
      corner = 0;
    } else if (key == "endsolid") {
      ended = true;
      break;
    } else if (key != "facet" && key != "outer" && key != "endfacet" && key != "solid") {
      s.fail("unexpected '" + std::string(key.substr(0, 20)) + "' in ASCII STL");
    }
    s.skip_line();
  }
  if (corner != 0 || !ended) s.fail("ASCII STL ends inside a facet or without 'endsolid' (truncated?)");
  return mesh;
}

}  // namespace

Mesh read_stl(std::string_view data, const std::string& file, std::vector<std::string>& warnings) {
  (void)warnings;
  if (data.size() >= 84) {
    std::uint32_t n;
    std::memcpy(&n, data.data() + 80, 4);
    if (84 + 50 * static_cast<std::uint64_t>(n) == data.size()) {
      if (n == 0) throw InputError(file + ": binary STL contains no triangles");
      return read_binary_stl(data, n);
    }
  }
  std::size_t i = 0;
  while (i < data.size() && (data[i] == ' ' || data[i] == '\t' || data[i] == '\r' || data[i] == '\n')) ++i;
  if (data.substr(i, 5) == "solid") {
    // Binary files may also start with "solid" in their header; only treat as text if it parses.
    bool text = true;
    for (char c : data.substr(0, std::min<std::size_t>(data.size(), 4096)))
      if (static_cast<unsigned char>(c) < 9 || (static_cast<unsigned char>(c) > 13 && static_cast<unsigned char>(c) < 32)) text = false;
    if (text) {
      Mesh m = read_ascii_stl(data, file);
      if (m.faces.empty()) throw InputError(file + ": ASCII STL contains no triangles");
      return m;
    }
  }
  if (data.size() >= 84) {
    std::uint32_t n;
    std::memcpy(&n, data.data() + 80, 4);
    throw InputError(file + ": not a valid STL: as binary STL its header announces " + std::to_string(n) +
                     " triangles (" + std::to_string(84 + 50 * static_cast<std::uint64_t>(n)) + " bytes) but the file has " +
                     std::to_string(data.size()) + " bytes, and it is not ASCII STL ('solid ...')");
  }
  throw InputError(file + ": not a valid STL: too short for binary STL (" + std::to_string(data.size()) +
                   " bytes) and not ASCII STL");
}

Mesh read_stl_file(const std::string& path, std::vector<std::string>& warnings, std::size_t chunk_bytes) {
  auto whole = [&] { return read_stl(read_file(path), path, warnings); };
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size < 84) return whole();  // read_file / read_stl say what is wrong
  FileChunks chunks(path, chunk_bytes);
  std::string_view window = chunks.next(0);
  while (window.size() < 84 && chunks.fresh() > 0) window = chunks.next(window.size());
  if (window.size() < 84) return whole();
  std::uint32_t n;
  std::memcpy(&n, window.data() + 80, 4);
  // Only a binary file whose size its triangle count explains streams (what read_stl takes as binary);
  // everything else, text STL included, is read whole.
  if (n == 0 || 84 + 50 * static_cast<std::uint64_t>(n) != size) return whole();
  Mesh mesh;
  Welder weld(mesh);
  mesh.faces.reserve(n);
  std::size_t start = 84;
  for (;;) {
    const std::size_t whole_records = (window.size() - start) / 50 * 50;
    add_binary_records(window.substr(start, whole_records), weld, mesh);
    const std::size_t keep = window.size() - start - whole_records;
    window = chunks.next(keep);
    start = 0;
    if (chunks.fresh() == 0) break;
  }
  if (mesh.faces.size() != n)
    throw InputError(path + ": binary STL changed while it was read (" + std::to_string(mesh.faces.size()) + " of " +
                     std::to_string(n) + " triangles)");
  return mesh;
}

void write_stl(const Mesh& mesh, bool binary, const ByteSink& sink) {
  std::string out;
  if (binary) {
    out.assign(80, ' ');
    std::memcpy(out.data(), "binary STL written by scanmesh", 30);
    const auto n = static_cast<std::uint32_t>(mesh.num_faces());
    out.append(reinterpret_cast<const char*>(&n), 4);
    for (const Face& f : mesh.faces) {
      const Vec3 nrm = (mesh.positions[f[1]] - mesh.positions[f[0]]).cross(mesh.positions[f[2]] - mesh.positions[f[0]]).normalized();
      float buf[12];
      for (int c = 0; c < 3; ++c) buf[c] = std::isfinite(nrm[c]) ? static_cast<float>(nrm[c]) : 0.0f;
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) buf[3 + 3 * k + c] = static_cast<float>(mesh.positions[f[k]][c]);
      out.append(reinterpret_cast<const char*>(buf), 48);
      out.append(2, '\0');
      flush_if_full(out, sink);
    }
    sink(out);
    return;
  }
  out = "solid scanmesh\n";
  for (const Face& f : mesh.faces) {
    Vec3 nrm = (mesh.positions[f[1]] - mesh.positions[f[0]]).cross(mesh.positions[f[2]] - mesh.positions[f[0]]).normalized();
    if (!nrm.allFinite()) nrm.setZero();
    out += "facet normal ";
    for (int c = 0; c < 3; ++c) {
      append_double(out, nrm[c]);
      out += c < 2 ? ' ' : '\n';
    }
    out += " outer loop\n";
    for (int k = 0; k < 3; ++k) {
      out += "  vertex ";
      for (int c = 0; c < 3; ++c) {
        append_double(out, mesh.positions[f[k]][c]);
        out += c < 2 ? ' ' : '\n';
      }
    }
    out += " endloop\nendfacet\n";
    flush_if_full(out, sink);
  }
  out += "endsolid scanmesh\n";
  sink(out);
}

}  // namespace scanmesh::detail
