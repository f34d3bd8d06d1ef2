#pragma once
// The indexed triangle mesh every scanmesh stage reads and writes.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace scanmesh {

using Vec3 = Eigen::Vector3d;
using Face = std::array<int, 3>;

/// Scalar type a per-vertex property had in its file; writers reproduce it.
enum class ScalarType : std::uint8_t { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

/// One extra scalar per vertex (a colour channel, a normal component, a scanner "value", ...).
/// Names follow PLY conventions: normals are nx/ny/nz, colours red/green/blue/alpha.
struct VertexProperty {
  std::string name;
  ScalarType type = ScalarType::float32;
  std::vector<double> values;  ///< one entry per vertex, in vertex order
};

/// Indexed triangle mesh. Vertex order is whatever the file had: it is never changed, so an output can
/// be compared vertex by vertex and face by face with a reference.
struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Face> faces;                       ///< counter-clockwise seen from outside
  std::vector<VertexProperty> vertex_properties;  ///< extra per-vertex data carried through every stage

  [[nodiscard]] std::size_t num_vertices() const { return positions.size(); }
  [[nodiscard]] std::size_t num_faces() const { return faces.size(); }

  /// The property with this name, or nullptr.
  [[nodiscard]] const VertexProperty* find_property(const std::string& name) const;
  [[nodiscard]] VertexProperty* find_property(const std::string& name);
};

/// The corner of face `f` that is not on its edge (a, b); -1 if every corner is a or b.
inline int opposite_corner(const Face& f, int a, int b) {
  for (int v : f)
    if (v != a && v != b) return v;
  return -1;
}

/// Throws InputError (naming `what`, e.g. the file) if a face index is out of range or a coordinate is
/// not finite, or a property has the wrong length.
void validate_mesh(const Mesh& mesh, const std::string& what);

}  // namespace scanmesh
