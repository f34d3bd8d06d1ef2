#include "scanmesh/mesh.h"

#include <cmath>

#include "scanmesh/errors.h"

namespace scanmesh {

const VertexProperty* Mesh::find_property(const std::string& name) const {
  for (const auto& p : vertex_properties)
    if (p.name == name) return &p;
  return nullptr;
}

VertexProperty* Mesh::find_property(const std::string& name) {
  for (auto& p : vertex_properties)
    if (p.name == name) return &p;
  return nullptr;
}

void validate_mesh(const Mesh& mesh, const std::string& what) {
  const auto n = static_cast<long long>(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!mesh.positions[i].allFinite())
      throw InputError(what + ": vertex " + std::to_string(i) + " has a coordinate that is NaN or infinite");
  }
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const long long v = mesh.faces[f][k];
      if (v < 0 || v >= n)
        throw InputError(what + ": face " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                         ", but there are only " + std::to_string(n) + " vertices");
    }
  }
  for (const auto& p : mesh.vertex_properties) {
    if (p.values.size() != mesh.positions.size())
      throw InputError(what + ": vertex property '" + p.name + "' has " + std::to_string(p.values.size()) +
                       " values for " + std::to_string(n) + " vertices");
  }
}

}  // namespace scanmesh
