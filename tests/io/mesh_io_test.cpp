#include "scanmesh/mesh_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "helpers.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/errors.h"

using namespace scanmesh;
namespace fs = std::filesystem;

namespace {

class MeshIo : public scanmesh::test::TempDirTest {
 protected:
  // Expects read_mesh to fail with an InputError naming the file and containing `needle`.
  void expect_error(const std::string& file, const std::string& needle) const {
    try {
      read_mesh(file);
      ADD_FAILURE() << "no error for " << file;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(fs::path(file).filename().string()), std::string::npos) << msg;
      EXPECT_NE(msg.find(needle), std::string::npos) << "'" << needle << "' not in: " << msg;
    }
  }
};

Mesh irrational_mesh() {
  Mesh m = test::make_sphere(1);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  for (auto& p : m.positions) p += Vec3(u(rng), u(rng), u(rng)) * std::sqrt(2.0);
  return m;
}

}  // namespace

TEST_F(MeshIo, ExactRoundTripObjOffPly) {
  const Mesh m = irrational_mesh();
  for (const std::string name : {"a.obj", "a.off", "a.ply"}) {
    for (bool binary : {false, true}) {
      WriteOptions w;
      w.binary = binary;
      write_mesh(m, path(name), w);
      const Mesh r = read_mesh(path(name));
      EXPECT_EQ(r.faces, m.faces) << name;
      ASSERT_EQ(r.positions.size(), m.positions.size()) << name;
      for (std::size_t v = 0; v < m.num_vertices(); ++v) EXPECT_EQ(r.positions[v], m.positions[v]) << name << " " << v;
    }
  }
}

TEST_F(MeshIo, StlRoundTripWeldsVertices) {
  const Mesh m = test::make_sphere(2);
  for (bool binary : {false, true}) {
    WriteOptions w;
    w.binary = binary;
    write_mesh(m, path("a.stl"), w);
    const Mesh r = read_mesh(path("a.stl"));
    ASSERT_EQ(r.num_vertices(), m.num_vertices());
    ASSERT_EQ(r.num_faces(), m.num_faces());
    // Vertices come in order of first appearance; faces map onto the same triangles.
    for (std::size_t f = 0; f < m.num_faces(); ++f)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR((r.positions[r.faces[f][k]] - m.positions[m.faces[f][k]]).norm(), 0.0, 1e-6);
  }
}

TEST_F(MeshIo, PlyKeepsVertexPropertiesAndTypes) {
  Mesh m = test::make_grid(2);
  const std::size_t n = m.num_vertices();
  VertexProperty red{"red", ScalarType::uint8, {}}, nz{"nz", ScalarType::float32, {}}, value{"value", ScalarType::float64, {}};
  VertexProperty label{"label", ScalarType::int32, {}};
  for (std::size_t v = 0; v < n; ++v) {
    red.values.push_back(static_cast<double>(v * 20 % 256));
    nz.values.push_back(0.5);
    value.values.push_back(1.0 / (1.0 + static_cast<double>(v)));
    label.values.push_back(-static_cast<double>(v));
  }
  m.vertex_properties = {red, nz, value, label};
  for (bool binary : {false, true}) {
    WriteOptions w;
    w.binary = binary;
    write_mesh(m, path("p.ply"), w);
    const Mesh r = read_mesh(path("p.ply"));
    ASSERT_EQ(r.vertex_properties.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_EQ(r.vertex_properties[i].name, m.vertex_properties[i].name);
      EXPECT_EQ(r.vertex_properties[i].type, m.vertex_properties[i].type);
      EXPECT_EQ(r.vertex_properties[i].values, m.vertex_properties[i].values) << m.vertex_properties[i].name;
    }
  }
}

TEST_F(MeshIo, ReadsBigEndianPlyAndSkipsOtherElements) {
  std::string s =
      "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nelement camera 1\nproperty int id\nend_header\n";
  auto be32 = [&s](const void* p) {
    const char* c = static_cast<const char*>(p);
    for (int i = 3; i >= 0; --i) s.push_back(c[i]);
  };
  const float coords[9] = {0, 0, 0, 1, 0, 0, 0, 2, 0.5f};
  for (float c : coords) be32(&c);
  s.push_back(3);
  for (int i : {0, 1, 2}) be32(&i);
  const int id = 7;
  be32(&id);
  std::vector<std::string> warnings;
  const Mesh r = read_mesh(write("be.ply", s), &warnings);
  ASSERT_EQ(r.num_vertices(), 3u);
  EXPECT_EQ(r.positions[2], Vec3(0, 2, 0.5));
  EXPECT_EQ(r.faces[0], (Face{0, 1, 2}));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("camera"), std::string::npos);
}

TEST_F(MeshIo, ObjPolygonsNegativeIndicesCrlfAndColours) {
  const std::string f = write("q.obj",
                              "# quad\r\nv 0 0 0 1 0 0\r\nv 1 0 0 0 1 0\r\nv 1 1 0 0 0 1\r\nv 0 1 0 1 1 1\r\nvn 0 0 1\r\n"
                              "f 1//1 2//1 3//1 4//1\r\nf -4 -2 -1\r\n");
  std::vector<std::string> warnings;
  const Mesh m = read_mesh(f, &warnings);
  ASSERT_EQ(m.num_faces(), 3u);
  EXPECT_EQ(m.faces[0], (Face{0, 1, 2}));
  EXPECT_EQ(m.faces[1], (Face{0, 2, 3}));
  EXPECT_EQ(m.faces[2], (Face{0, 2, 3}));
  bool triangulated = false;
  for (const auto& w : warnings) triangulated = triangulated || w.find("fan-triangulated") != std::string::npos;
  EXPECT_TRUE(triangulated);
  ASSERT_NE(m.find_property("green"), nullptr);
  EXPECT_EQ(m.find_property("green")->values[1], 255.0);
}

TEST_F(MeshIo, FacesNamingAVertexTwiceAreKeptAndSaid) {
  // Collapsed triangles stay (dropping them could open the surface), with one warning that counts them and
  // names the first; a mesh without any gets no warning.
  std::vector<std::string> warnings;
  const Mesh m = read_mesh(write("c.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 0 3\n3 1 2 1\n3 0 1 3\n"), &warnings);
  EXPECT_EQ(m.num_faces(), 4u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("c.off: 2 faces name a vertex twice (first: face 1, vertices 0 0 3)"), std::string::npos) << warnings[0];
  warnings.clear();
  read_mesh(write("t.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), &warnings);
  EXPECT_TRUE(warnings.empty());
}

TEST_F(MeshIo, OffWithCommentsAndPolygons) {
  const Mesh m = read_mesh(write("p.off", "OFF\n# comment\n5 1 0\n0 0 0\n1 0 0\n1 1 0\n0.5 2 0\n0 1 0\n5 0 1 2 3 4\n"));
  EXPECT_EQ(m.num_faces(), 3u);
  EXPECT_EQ(m.faces[2], (Face{0, 3, 4}));
}

TEST_F(MeshIo, BadInputsGiveClearErrors) {
  expect_error(path("missing.obj"), "No such file");
  expect_error(write("empty.ply", ""), "empty");
  expect_error(write("trunc.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2"), "fewer than three");
  expect_error(write("trunc.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n"), "truncated");
  expect_error(write("trunc_v.off", "OFF\n4 2 0\n0 0 0\n1 0"), "truncated");
  expect_error(write("trunc_hdr.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"), "end_header");
  expect_error(write("trunc_bin.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                      "property float y\nproperty float z\nelement face 1\n"
                                      "property list uchar int vertex_indices\nend_header\n" + std::string(20, '\0')),
               "truncated");
  expect_error(write("trunc_ascii.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                        "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n"),
               "truncated");
  expect_error(write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"), "NaN");
  expect_error(write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), "vertex 9");
  expect_error(write("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), "vertex 3");
  expect_error(write("range.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                  "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                  "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n"),
               "vertex 5");
  expect_error(write("noyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nelement face 0\n"
                                 "property list uchar int vertex_indices\nend_header\n0\n"),
               "'y'");
  std::mt19937 rng(1);
  std::string noise(1000, '\0');
  for (auto& c : noise) c = static_cast<char>(rng());
  expect_error(write("random.stl", noise), "not a valid STL");
  std::string empty_binary(84, '\0');
  expect_error(write("none.stl", empty_binary), "no triangles");
  expect_error(write("none_ascii.stl", "solid x\nendsolid x\n"), "no triangles");
  expect_error(write("mesh.xyz3", "1 2 3\n"), "unknown mesh format");
  expect_error(write("cloud.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                  "property float z\nend_header\n0 0 0\n"),
               "no 'face'");
  expect_error(write("nofaces.obj", "v 0 0 0\n"), "no faces");
  expect_error(write("garbage.off", "hello world\n"), "not an OFF");
  fs::create_directories(path("dir.obj"));
  expect_error(path("dir.obj"), "directory");
}

TEST_F(MeshIo, FailedWriteLeavesNoFile) {
  const Mesh m = test::make_grid(1);
  EXPECT_THROW(write_mesh(m, path("no/such/dir/out.ply")), OutputError);
  EXPECT_THROW(write_mesh(m, path("out.xyz3")), UsageError);
  EXPECT_FALSE(fs::exists(path("out.xyz3")));
  write_mesh(m, path("ok.ply"));
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir_)) files += e.path().filename().string()[0] == '.' ? 100 : 1;
  EXPECT_EQ(files, 1u) << "temporary files left behind";
}

TEST_F(MeshIo, WritersStreamTheirFilesInPiecesOfAboutAMegabyte) {
  // A sphere of 82k faces with a colour: a few megabytes in every format. Streamed, no piece is much
  // larger than a megabyte, the pieces add up to the file encode_mesh makes, and the written file reads
  // back to the same mesh.
  Mesh m = test::make_sphere(6);
  for (const char* c : {"red", "green", "blue"}) {
    VertexProperty p;
    p.name = c;
    p.type = ScalarType::uint8;
    p.values.assign(m.num_vertices(), 200.0);
    m.vertex_properties.push_back(p);
  }
  for (const char* ext : {".ply", ".obj", ".off", ".stl"})
    for (bool binary : {true, false}) {
      WriteOptions w;
      w.binary = binary;
      std::string joined;
      std::size_t pieces = 0, largest = 0;
      encode_mesh(m, ext, w, [&](std::string_view piece) {
        joined += piece;
        ++pieces;
        largest = std::max(largest, piece.size());
      });
      const std::string whole = encode_mesh(m, ext, w);
      EXPECT_GT(whole.size(), 2u << 20) << ext;
      EXPECT_EQ(joined, whole) << ext;
      EXPECT_GT(pieces, 2u) << ext;
      EXPECT_LT(largest, (1u << 20) + 4096) << ext;
      const std::string file = path(std::string("s") + (binary ? "b" : "a") + ext);
      write_mesh(m, file, w);
      EXPECT_EQ(read_file(file), whole) << ext;
    }
}
