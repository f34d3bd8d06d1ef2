// A PLY file's body read a chunk at a time (read_ply_file; a text body a block of whole lines at a time),
// OBJ and OFF files read a block of lines at a time (read_obj_file, read_off_file) and binary STL files a
// chunk of whole triangles at a time (read_stl_file), what read_mesh does for big files, give what reading
// the whole file gives: the same mesh, warnings and errors (line numbers included), at any chunk size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <random>

#include "formats.h"
#include "helpers.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/cloud_io.h"
#include "scanmesh/errors.h"
#include "scanmesh/mesh_io.h"

using namespace scanmesh;

namespace {

class ChunkedReading : public test::TempDirTest {
 protected:
  // The outcome of a read as text: the mesh's bytes (or the error) and the warnings.
  static std::string outcome(const std::function<Mesh(std::vector<std::string>&)>& read) {
    std::vector<std::string> warnings;
    std::string result;
    try {
      const Mesh m = read(warnings);
      result = encode_mesh(m, ".ply") + "|" + std::to_string(m.vertex_properties.size());
    } catch (const InputError& e) {
      result = std::string("error: ") + e.what();
    }
    for (const auto& w : warnings) result += "|" + w;
    return result;
  }
  // Writes `bytes` to `name` and expects `chunked` to give at every chunk size what `whole` gives for the
  // file held in memory; returns that outcome.
  using WholeReader = Mesh (*)(std::string_view, const std::string&, std::vector<std::string>&);
  using ChunkedReader = Mesh (*)(const std::string&, std::vector<std::string>&, std::size_t);
  std::string same_outcome(const std::string& name, const std::string& bytes, WholeReader whole_reader, ChunkedReader chunked,
                           std::initializer_list<std::size_t> chunks) {
    const std::string file = write(name, bytes);
    const std::string whole = outcome([&](auto& w) { return whole_reader(read_file(file), file, w); });
    for (std::size_t chunk : chunks)
      EXPECT_EQ(outcome([&](auto& w) { return chunked(file, w, chunk); }), whole) << name << " " << chunk;
    return whole;
  }
  void expect_same(const std::string& file) {
    const std::string whole = outcome([&](auto& w) { return detail::read_ply(read_file(file), file, w); });
    for (std::size_t chunk : {64, 97, 1000, 1 << 20})
      EXPECT_EQ(outcome([&](auto& w) { return detail::read_ply_file(file, w, true, nullptr, chunk); }), whole) << chunk;
  }
};

TEST_F(ChunkedReading, BinaryBodiesReadInChunksGiveTheSameMesh) {
  Mesh m = test::make_sphere(3);
  m.vertex_properties.push_back({"quality", ScalarType::float32, std::vector<double>(m.num_vertices(), 0.25)});
  m.vertex_properties.push_back({"red", ScalarType::uint8, std::vector<double>(m.num_vertices(), 200.0)});
  const std::string file = path("sphere.ply");
  write_mesh(m, file);
  expect_same(file);
  ASSERT_GT(read_file(file).size(), 20000u);  // many chunks of 64-1000 bytes
  // The body cut in the middle of a face: the same "truncated" error.
  const std::string bytes = read_file(file);
  expect_same(write("cut.ply", bytes.substr(0, bytes.size() - 7)));
  // A header whose counts the file cannot hold, and a text body (read a block of whole lines at a time),
  // whole, with a bad index on its last line, and without the newline at its end.
  std::string lying = bytes;
  lying.replace(lying.find("element face ") + 13, 4, "9999");
  expect_same(write("lying.ply", lying));
  write_mesh(m, path("text.ply"), WriteOptions{false});
  expect_same(path("text.ply"));
  std::string text = read_file(path("text.ply"));
  ASSERT_EQ(text.back(), '\n');
  expect_same(write("text-no-newline.ply", text.substr(0, text.size() - 1)));
  const std::size_t last = text.rfind('\n', text.size() - 2) + 1;
  text.replace(last, text.size() - last, "3 0 1 999999\n");
  expect_same(write("text-bad-index.ply", text));
  EXPECT_NE(outcome([&](auto& w) { return detail::read_ply_file(path("text-bad-index.ply"), w, true, nullptr, 64); }).find("999999"),
            std::string::npos);
  EXPECT_NE(outcome([&](auto& w) { return detail::read_ply_file(path("cut.ply"), w, true, nullptr, 64); }).find("truncated"), std::string::npos);
}

TEST_F(ChunkedReading, TriangleStripsAndSkippedElements) {
  // Big-endian, a tristrips element with restarts, and an element that is skipped (warned about).
  std::string body;
  auto be32 = [&](std::uint32_t v) {
    for (int k = 3; k >= 0; --k) body += static_cast<char>((v >> (8 * k)) & 0xff);
  };
  auto bef = [&](float f) {
    std::uint32_t v;
    std::memcpy(&v, &f, 4);
    be32(v);
  };
  for (int i = 0; i < 40; ++i) bef(static_cast<float>(i % 8)), bef(static_cast<float>(i / 8)), bef(0.0f);
  body += static_cast<char>(3);
  be32(1), be32(2), be32(3);
  be32(9);
  for (std::int32_t v : {0, 8, 1, 9, -1, 10, 18, 11, 19}) be32(static_cast<std::uint32_t>(v));
  const std::string header =
      "ply\nformat binary_big_endian 1.0\nelement vertex 40\nproperty float x\nproperty float y\nproperty float z\n"
      "element junk 1\nproperty list uchar int stuff\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n";
  const std::string file = write("strips.ply", header + body);
  std::vector<std::string> warnings;
  EXPECT_EQ(detail::read_ply(read_file(file), file, warnings).faces.size(), 4u);
  EXPECT_EQ(warnings.size(), 1u);  // junk is not kept
  expect_same(file);
}

TEST_F(ChunkedReading, ObjReadInBlocksOfLinesGivesTheSameMeshAndErrors) {
  auto same = [&](const std::string& name, const std::string& text) {
    return same_outcome(name, text, detail::read_obj, detail::read_obj_file, {16, 37, 1000});
  };
  // Colours, comments, blank lines, CRLF, vt/vn, a quad, negative indices, a line longer than a chunk,
  // no newline at the end.
  std::string obj = "# made by hand\r\n\nv 0 0 0 1 0 0\r\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 0.5 0.5 0.5\nvt 0 0\nvn 0 0 1\n";
  obj += "f 1/1/1 2/1/1 3/1/1 4/1/1\n";
  obj += "f -4 -3 -2";
  for (int i = 0; i < 30; ++i) obj += "   ";
  obj += "\n# the end";
  EXPECT_EQ(same("hand.obj", obj).find("error"), std::string::npos);
  // A sphere written by the OBJ writer; errors on a late line keep their line numbers.
  const std::string sphere = encode_mesh(test::make_sphere(2), ".obj");
  same("sphere.obj", sphere);
  const std::string bad = same("bad.obj", sphere + "f 1 2 999999\n");
  std::string expected = std::to_string(std::count(sphere.begin(), sphere.end(), '\n') + 1);
  expected += ": face refers to vertex 999999";
  EXPECT_NE(bad.find(expected), std::string::npos) << bad;
  same("nan.obj", sphere.substr(0, sphere.size() / 2) + "\nv 1 nan 2\n");
}

TEST_F(ChunkedReading, OffReadInBlocksOfLinesGivesTheSameMeshAndErrors) {
  auto same = [&](const std::string& name, const std::string& text) {
    return same_outcome(name, text, detail::read_off, detail::read_off_file, {16, 37, 1000});
  };
  // Comments, blank lines, CRLF, colours, a vertex whose coordinates run over three lines (blocks end
  // inside it), a quad, a line longer than a chunk, no newline at the end.
  std::string off = "COFF\r\n# made by hand\n\n4 2 0\n0 0 0 255 0 0\n1\n# between coordinates\n0\n0 0 255 0\n";
  off += "1 1 0 0 0 255\n0 1 0 128 128 128\n";
  off += "4 0 1 2 3";
  for (int i = 0; i < 30; ++i) off += "   ";
  off += "\n3 0 2 3";
  const std::string hand = same("hand.off", off);
  EXPECT_EQ(hand.find("error"), std::string::npos) << hand;
  EXPECT_NE(hand.find("|3|"), std::string::npos) << hand;  // the three colour channels
  // The header keyword left out, as some writers do.
  EXPECT_EQ(same("bare.off", "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").find("error"), std::string::npos);
  // A sphere written by the OFF writer; errors on a late line keep their line numbers.
  const std::string sphere = encode_mesh(test::make_sphere(2), ".off");
  same("sphere.off", sphere);
  std::string late = sphere;
  const std::size_t last_face = late.rfind("\n3 ") + 1;
  late.replace(last_face, late.size() - last_face, "3 0 1 999999\n");
  const std::string bad = same("bad.off", late);
  std::string expected = std::to_string(std::count(late.begin(), late.end(), '\n'));
  expected += ": face " + std::to_string(test::make_sphere(2).num_faces() - 1) + " refers to vertex 999999";
  EXPECT_NE(bad.find(expected), std::string::npos) << bad;
  EXPECT_NE(same("cut.off", sphere.substr(0, sphere.size() / 3)).find("truncated"), std::string::npos);
  EXPECT_NE(same("empty.off", "OFF\n# nothing\n").find("counts"), std::string::npos);
}

TEST_F(ChunkedReading, BinaryStlReadInChunksOfWholeTrianglesGivesTheSameMesh) {
  auto same = [&](const std::string& name, const std::string& bytes) {
    return same_outcome(name, bytes, detail::read_stl, detail::read_stl_file, {16, 37, 97, 1000, 1 << 20});
  };
  const Mesh sphere = test::make_sphere(3);
  const std::string binary = encode_mesh(sphere, ".stl");
  ASSERT_GT(binary.size(), 20000u);  // many chunks
  const std::string welded = same("sphere.stl", binary);
  EXPECT_EQ(welded.find("error"), std::string::npos);
  // The corners are welded across chunks: the sphere's vertices and faces come back.
  std::vector<std::string> warnings;
  const Mesh read = detail::read_stl_file(path("sphere.stl"), warnings, 37);
  EXPECT_EQ(read.num_vertices(), sphere.num_vertices());
  EXPECT_EQ(read.num_faces(), sphere.num_faces());
  // A count the size does not explain, a count of zero, a text STL, too short a file: read whole.
  std::string lying = binary;
  lying[80] = static_cast<char>(lying[80] + 1);
  EXPECT_NE(same("lying.stl", lying).find("error"), std::string::npos);
  EXPECT_NE(same("empty.stl", binary.substr(0, 80) + std::string(4, '\0')).find("no triangles"), std::string::npos);
  same("text.stl", encode_mesh(sphere, ".stl", WriteOptions{false}));
  same("short.stl", binary.substr(0, 50));
}

// A PLY cloud over 16 MiB (read_cloud streams its body) gives the cloud the whole file gives: points,
// normals and colours, binary and text.
TEST_F(ChunkedReading, BigPlyCloudsReadInChunksGiveTheSameCloud) {
  PointCloud c;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 450000; ++i) {
    c.points.emplace_back(u(rng), u(rng), u(rng));
    c.normals.push_back(Vec3(u(rng), u(rng), u(rng)).normalized());
    c.colours.push_back({static_cast<std::uint8_t>(i % 256), static_cast<std::uint8_t>(i / 256 % 256), 7});
  }
  c.width = static_cast<int>(c.size());
  const std::string binary = encode_cloud(c, ".ply");
  ASSERT_GT(binary.size(), std::size_t{16} << 20);  // over read_cloud's whole-file limit
  const std::string file = write("big.ply", binary);
  const PointCloud whole = decode_cloud(binary, file);
  const PointCloud streamed = read_cloud(file);
  EXPECT_EQ(streamed.points, whole.points);
  EXPECT_EQ(streamed.normals, whole.normals);
  EXPECT_EQ(streamed.colours, whole.colours);
  EXPECT_EQ(streamed.points, c.points);  // doubles written and read back exactly
  // Cut inside the body: the same "truncated" error either way.
  const std::string cut = write("cut.ply", binary.substr(0, binary.size() - 5));
  auto error = [](const std::function<PointCloud()>& read) {
    try {
      read();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string a = error([&] { return decode_cloud(read_file(cut), cut); });
  const std::string b = error([&] { return read_cloud(cut); });
  EXPECT_NE(a.find("truncated"), std::string::npos) << a;
  EXPECT_EQ(a, b);
}

TEST_F(ChunkedReading, MutatedFilesGiveTheSameOutcomeInChunksAsWhole) {
  // Truncated, byte-flipped and number-swapped PLY (binary and text), OBJ, OFF and binary STL files: the chunked readers
  // load the same mesh or fail with the same message as the whole-file readers.
  const Mesh m = test::make_sphere(2);
  std::vector<std::pair<std::string, std::string>> valid;
  valid.emplace_back(".ply", encode_mesh(m, ".ply"));
  valid.emplace_back(".ply", encode_mesh(m, ".ply", WriteOptions{false}));
  valid.emplace_back(".obj", encode_mesh(m, ".obj"));
  valid.emplace_back(".off", encode_mesh(m, ".off"));
  valid.emplace_back(".stl", encode_mesh(m, ".stl"));
  int compared = 0;
  for (const auto& entry : valid) {
    const std::string& ext = entry.first;  // not a structured binding: lambdas below capture it (C++17)
    const std::string& text = entry.second;
    std::mt19937 rng(static_cast<unsigned>(text.size()));
    for (int round = 0; round < 90; ++round) {
      std::string bytes = text;
      if (round % 3 == 0) {
        bytes.resize(std::uniform_int_distribution<std::size_t>(0, bytes.size())(rng));
      } else if (round % 3 == 1) {
        for (int k = 0; k < 4 && !bytes.empty(); ++k)
          bytes[std::uniform_int_distribution<std::size_t>(0, bytes.size() - 1)(rng)] = static_cast<char>(rng());
      } else if (const auto p = bytes.find_first_of("123456789", std::uniform_int_distribution<std::size_t>(0, bytes.size())(rng));
                 p != std::string::npos) {
        bytes.replace(p, 1, round % 2 ? "99999999999" : "-7");
      }
      const std::string file = write("m" + ext, bytes);
      const std::string whole = outcome([&](auto& w) {
        if (ext == ".ply") return detail::read_ply(read_file(file), file, w);
        if (ext == ".stl") return detail::read_stl(read_file(file), file, w);
        return ext == ".obj" ? detail::read_obj(read_file(file), file, w) : detail::read_off(read_file(file), file, w);
      });
      const std::string chunked = outcome([&](auto& w) {
        if (ext == ".ply") return detail::read_ply_file(file, w, true, nullptr, 64);
        if (ext == ".stl") return detail::read_stl_file(file, w, 64);
        return ext == ".obj" ? detail::read_obj_file(file, w, 16) : detail::read_off_file(file, w, 16);
      });
      EXPECT_EQ(chunked, whole) << ext << " round " << round;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 450);
}

}  // namespace
