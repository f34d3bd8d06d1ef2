// Writing PLY: ascii or binary little endian, every per-vertex property with its type.
#include <bit>
#include <cstring>
#include <string>

#include "formats.h"
#include "text_scanner.h"

namespace scanmesh::detail {

namespace {

template <typename T>
void store(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if constexpr (std::endian::native == std::endian::big)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  out.append(b, sizeof(T));
}

void store_as(std::string& out, ScalarType t, double v) {
  switch (t) {
    case ScalarType::int8: store(out, static_cast<std::int8_t>(v)); break;
    case ScalarType::uint8: store(out, static_cast<std::uint8_t>(v)); break;
    case ScalarType::int16: store(out, static_cast<std::int16_t>(v)); break;
    case ScalarType::uint16: store(out, static_cast<std::uint16_t>(v)); break;
    case ScalarType::int32: store(out, static_cast<std::int32_t>(v)); break;
    case ScalarType::uint32: store(out, static_cast<std::uint32_t>(v)); break;
    case ScalarType::float32: store(out, static_cast<float>(v)); break;
    case ScalarType::float64: store(out, v); break;
  }
}

void append_ascii(std::string& out, ScalarType t, double v) {
  if (t == ScalarType::float32) append_double(out, static_cast<double>(static_cast<float>(v)));
  else if (t == ScalarType::float64) append_double(out, v);
  else append_int(out, static_cast<long long>(v));
}

}  // namespace

void write_ply(const Mesh& mesh, bool binary, const ByteSink& sink) {
  std::string out = "ply\nformat ";
  out += binary ? "binary_little_endian" : "ascii";
  out += " 1.0\ncomment written by scanmesh\nelement vertex ";
  append_int(out, static_cast<long long>(mesh.num_vertices()));
  out += "\nproperty double x\nproperty double y\nproperty double z\n";
  for (const auto& p : mesh.vertex_properties) {
    out += "property ";
    out += ply_type_name(p.type);
    out += ' ';
    out += p.name;
    out += '\n';
  }
  out += "element face ";
  append_int(out, static_cast<long long>(mesh.num_faces()));
  out += "\nproperty list uchar int vertex_indices\nend_header\n";
  const std::size_t nv = mesh.num_vertices();
  if (binary) {
    for (std::size_t v = 0; v < nv; ++v) {
      for (int c = 0; c < 3; ++c) store(out, mesh.positions[v][c]);
      for (const auto& p : mesh.vertex_properties) store_as(out, p.type, p.values[v]);
      flush_if_full(out, sink);
    }
    for (const Face& f : mesh.faces) {
      store(out, static_cast<std::uint8_t>(3));
      for (int k = 0; k < 3; ++k) store(out, static_cast<std::int32_t>(f[k]));
      flush_if_full(out, sink);
    }
  } else {
    for (std::size_t v = 0; v < nv; ++v) {
      for (int c = 0; c < 3; ++c) {
        append_double(out, mesh.positions[v][c]);
        out += ' ';
      }
      for (const auto& p : mesh.vertex_properties) {
        append_ascii(out, p.type, p.values[v]);
        out += ' ';
      }
      out.back() = '\n';
      flush_if_full(out, sink);
    }
    append_counted_faces(out, mesh.faces, sink);
  }
  sink(out);
}

}  // namespace scanmesh::detail
