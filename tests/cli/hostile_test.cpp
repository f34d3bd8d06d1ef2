// Crafted hostile input (tests/hostile, made by make_cases.py) and pathological meshes built here: each
// must end in exit code 1 with a message naming the file and the problem (or, for valid but pathological
// meshes, succeed), never a signal, and with peak memory bounded by the input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <thread>
#include <tuple>

#include "helpers.h"
#include "run_cli.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/mesh_io.h"

namespace fs = std::filesystem;
using scanmesh::test::Outcome;
using scanmesh::test::run_scanmesh;

namespace {

class Hostile : public scanmesh::test::TempDirTest {};

struct Case {
  const char* file;
  const char* command;  ///< "mesh" for clouds, "eval" for meshes
  const char* needle;   ///< part of the expected message
};

const Case kCases[] = {
    {"pcd-negative-count.pcd", "mesh", "COUNT must be"},
    {"pcd-overflow-count.pcd", "mesh", "COUNT must be"},
    {"pcd-huge-count.pcd", "mesh", "COUNT must be"},
    {"pcd-negative-size.pcd", "mesh", "SIZE must be"},
    {"pcd-size-count-overflow.pcd", "mesh", "COUNT must be"},
    {"pcd-claims-5e8-points.pcd", "mesh", "truncated"},
    {"pcd-width-height-overflow.pcd", "mesh", "more points than any file can hold"},
    {"pcd-compressed-zero-size.pcd", "mesh", "expands to 0 bytes"},
    {"pcd-compressed-huge-size.pcd", "mesh", "corrupt"},
    {"pcd-compressed-count-mismatch.pcd", "mesh", "10 points of 12 bytes need 120"},
    {"pcd-compressed-corrupt.pcd", "mesh", "corrupt"},
    {"xyz-float-overflow.xyz", "mesh", "point 2 has a coordinate beyond"},
    {"xyz-double-overflow.xyz", "mesh", ":3: '1e999' is too large"},
    {"ply-many-properties.ply", "mesh", "cannot hold them"},
    {"range-grid-wrong-cols.ply", "mesh", "num_cols x num_rows = 8 x 4"},
    {"range-grid-bad-index.ply", "mesh", "refers to vertex 1000"},
    {"obj-double-overflow.obj", "eval", ":3: vertex 3: '1e309' is too large"},
    {"off-double-overflow.off", "eval", "'1e309' is too large"},
    {"ply-double-overflow.ply", "eval", "'1e309' in vertex 2 of 3 is too large"},
    {"stl-double-overflow.stl", "eval", "'1e309' is too large"},
    {"ply-index-beyond-integers.ply", "eval", "refers to vertex 1e+30"},
};

}  // namespace

TEST_F(Hostile, CraftedFilesFailCleanlyWithBoundedMemory) {
  for (const Case& c : kCases) {
    const std::string file = std::string(SCANMESH_HOSTILE_DIR) + "/" + c.file;
    ASSERT_TRUE(fs::exists(file)) << file;
    std::vector<std::string> args = {c.command, file};
    if (std::string(c.command) == "mesh") args.push_back(path("out.ply"));
    const Outcome o = run_scanmesh(args, path("err"));
    EXPECT_EQ(o.signal, 0) << c.file << ": killed by signal " << o.signal;
    EXPECT_EQ(o.exit_code, 1) << c.file << ": " << o.err;
    EXPECT_NE(o.err.find(c.file), std::string::npos) << c.file << ": message does not name the file: " << o.err;
    EXPECT_NE(o.err.find(c.needle), std::string::npos) << c.file << ": expected '" << c.needle << "' in: " << o.err;
    EXPECT_FALSE(fs::exists(path("out.ply"))) << c.file << ": an output was written";
#ifndef SCANMESH_SANITIZED
    // Peak memory of the whole process (the light binary or the one that loads PCL, ~100 MB), against
    // what the file could justify.
    const double bound_mb = 10.0 * static_cast<double>(fs::file_size(file)) / 1048576.0 + 200.0;
    EXPECT_LT(o.peak_mb, bound_mb) << c.file;
#endif
  }
}

namespace {

// k triangles on one edge (0,0,0)-(1,0,0), their third corners on a circle: one non-manifold edge.
std::string fan_off(int k) {
  std::string s = "OFF\n" + std::to_string(k + 2) + " " + std::to_string(k) + " 0\n0 0 0\n1 0 0\n";
  for (int i = 0; i < k; ++i) {
    const double t = 2.0 * M_PI * i / k;
    s += "0.5 " + std::to_string(0.5 * std::cos(t)) + " " + std::to_string(0.5 * std::sin(t)) + "\n";
  }
  for (int i = 0; i < k; ++i) s += "3 0 1 " + std::to_string(i + 2) + "\n";
  return s;
}

// `pages` unit squares (two triangles each) hinged on one spine edge.
std::string book_off(int pages) {
  std::string s = "OFF\n" + std::to_string(2 * pages + 2) + " " + std::to_string(2 * pages) + " 0\n0 0 0\n1 0 0\n";
  for (int i = 0; i < pages; ++i) {
    const double t = M_PI * i / pages;
    const std::string yz = std::to_string(std::cos(t)) + " " + std::to_string(std::sin(t));
    s += "1 " + yz + "\n0 " + yz + "\n";
  }
  for (int i = 0; i < pages; ++i)
    s += "3 0 1 " + std::to_string(2 + 2 * i) + "\n3 0 " + std::to_string(2 + 2 * i) + " " + std::to_string(3 + 2 * i) + "\n";
  return s;
}

}  // namespace

TEST_F(Hostile, NonManifoldFansAndBooksStayLinear) {
  // 20,000 faces on one edge, and 10,000 pages on one spine: every face's neighbourhood used to be the
  // whole fan (eval 30 s and 10 GB). They are valid meshes: eval and denoise must simply work.
#ifdef SCANMESH_SANITIZED
  const int faces = 2000;  // a tenth: the instrumented build is ~50x slower and checks memory safety, not size
#else
  const int faces = 20000;
#endif
  for (const auto& [name, text] : {std::pair{"fan.off", fan_off(faces)}, std::pair{"book.off", book_off(faces / 2)}}) {
    const std::string file = write(name, text);
    const Outcome e = run_scanmesh({"eval", file}, path("err"));
    EXPECT_EQ(e.exit_code, 0) << name << ": " << e.err;
    const Outcome d = run_scanmesh({"denoise", file, path("out.off"), "-q"}, path("err"));
    EXPECT_EQ(d.exit_code, 0) << name << ": " << d.err;
#ifndef SCANMESH_SANITIZED
    EXPECT_LT(e.peak_mb, 200.0) << name;
    EXPECT_LT(d.peak_mb, 400.0) << name;
#endif
  }
}

TEST_F(Hostile, ABoundaryOfTinyAndLongEdgesStaysLinear) {
#ifdef SCANMESH_SANITIZED
  GTEST_SKIP() << "a question of running time, which the instrumented build does not answer";
#else
  // A strip of 100,000 tiny faces whose boundary loop closes through one far vertex: the loop's mean edge,
  // which sets the boundary windows, spans thousands of tiny edges. Windows walked that far made each
  // iteration quadratic (30 iterations: ~3 minutes, past the 120 s hang guard); now they stop at
  // kBoundaryWindowMaxEdges (~5 s).
  const int n = 50000;
  const double w = 1e-3;
  std::string off = "OFF\n" + std::to_string(2 * n + 3) + " " + std::to_string(2 * n + 1) + " 0\n";
  char line[128];
  for (int i = 0; i <= n; ++i) {
    const double x = w * i / n, z = 1e-9 * ((i * 7919) % 13 - 6) / 6.0;  // a little roughness to denoise
    std::snprintf(line, sizeof line, "%.12g 0 %.12g\n%.12g %.12g %.12g\n", x, z, x, w / n, -z);
    off += line;
  }
  off += "0.5 -1 0\n";
  for (int i = 0; i < n; ++i) {
    const int a = 2 * i, b = a + 2, c = a + 3, d = a + 1;
    off += "3 " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + "\n3 " + std::to_string(a) + " " +
           std::to_string(c) + " " + std::to_string(d) + "\n";
  }
  off += "3 0 " + std::to_string(2 * n + 2) + " " + std::to_string(2 * n) + "\n";
  const std::string file = write("strip.off", off);
  const Outcome d = run_scanmesh({"denoise", file, path("out.off"), "--iterations", "30", "-q"}, path("err"));
  EXPECT_EQ(d.signal, 0) << "killed: a hang";
  EXPECT_EQ(d.exit_code, 0) << d.err;
  EXPECT_LT(d.peak_mb, 400.0);
#endif
}

TEST_F(Hostile, CloudsWithoutASurfaceFailAtOnce) {
  // 50,000 copies of one point (PCL's neighbour searches were quadratic on it: 69 s for 100,000 before the
  // message) and 50,000 points on a line.
  std::string same, line;
  for (int i = 0; i < 50000; ++i) {
    same += "1 2 3\n";
    line += std::to_string(i) + " " + std::to_string(2 * i) + " 0\n";
  }
  for (const auto& [name, text, needle] : {std::tuple{"same.xyz", same, "all points are at one position (1, 2, 3)"},
                                           std::tuple{"line.xyz", line, "all 50000 points lie on one line"}}) {
    const std::string file = write(name, text);
    const Outcome o = run_scanmesh({"mesh", file, path("out.ply")}, path("err"));
    EXPECT_EQ(o.exit_code, 1) << name << ": " << o.err;
    EXPECT_NE(o.err.find(needle), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(path("out.ply")));
  }
}

TEST_F(Hostile, ManyCopiesOfOnePointBesideASurfaceAreMerged) {
  // 50,000 copies of one point on a plane of 1,600: k-d trees cannot split the shared position, so every
  // neighbour search near it scanned all the copies (the read stage's spacing alone ran for minutes on
  // 200,000). The reader keeps the first of each position and says so; the plane is meshed.
#ifdef SCANMESH_SANITIZED
  const int copies = 5000;
#else
  const int copies = 50000;
#endif
  std::string text;
  char line[96];
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      std::snprintf(line, sizeof line, "%d %d %.4f\n", i, j, 0.01 * ((i * 7 + j * 13) % 5 - 2));
      text += line;
      if (i == 20 && j == 20)
        for (int c = 0; c < copies; ++c) text += line;
    }
  const std::string file = write("copies.xyz", text);
  const Outcome o = run_scanmesh({"mesh", file, path("out.ply")}, path("err"));
  EXPECT_EQ(o.signal, 0) << "killed: a hang";
  EXPECT_EQ(o.exit_code, 0) << o.err;
  EXPECT_NE(o.err.find(std::to_string(copies) + " copies of points merged"), std::string::npos) << o.err;
  ASSERT_TRUE(fs::exists(path("out.ply")));
  // The same cloud as the reference of eval (its spacing search had the same trouble).
  const Outcome e = run_scanmesh({"eval", path("out.ply"), "--reference", file}, path("err"));
  EXPECT_EQ(e.signal, 0) << "killed: a hang";
  EXPECT_EQ(e.exit_code, 0) << e.err;
  EXPECT_NE(e.err.find(std::to_string(copies) + " copies of points merged"), std::string::npos) << e.err;
}

TEST_F(Hostile, ManyCopiesOfOneFaceBesideASurface) {
  // A 30 x 30 grid and 30,000 copies of a triangle over half of it, each with its own three vertices (an
  // exporter's duplicates). A mesh keeps its faces, but the searches over face centroids cannot split a
  // position so many faces share: denoising took 20 s per 100,000 copies, eval's closest points and the
  // virtual scanner's rays scanned every copy (the scan ran for minutes and took gigabytes). Now each
  // search goes over distinct positions or distinct triangles. Each command gets 60 s (it takes well
  // under a second; eval took 75 s before, and the scan minutes).
#ifdef SCANMESH_SANITIZED
  const int copies = 3000;
#else
  const int copies = 30000;
#endif
  const int n = 30;
  scanmesh::Mesh m = scanmesh::test::make_grid(n - 1);
  for (int c = 0; c < copies; ++c) {  // over half the grid
    const int v = static_cast<int>(m.num_vertices());
    m.positions.insert(m.positions.end(), {{0, 0, 0}, {n - 1.0, 0, 0}, {0, n - 1.0, 0}});
    m.faces.push_back({v, v + 1, v + 2});
  }
  const std::string file = path("copies.off");
  scanmesh::write_mesh(m, file);
  const Outcome d = run_scanmesh({"denoise", file, path("out.ply")}, path("err"), 60.0);
  EXPECT_EQ(d.signal, 0) << "killed: a hang";
  EXPECT_EQ(d.exit_code, 0) << d.err;
  const Outcome e = run_scanmesh({"eval", file, "--reference", file, "--json", path("eval.json")}, path("err"), 60.0);
  EXPECT_EQ(e.signal, 0) << "killed: a hang";
  EXPECT_EQ(e.exit_code, 0) << e.err;
  EXPECT_NE(scanmesh::read_file(path("eval.json")).find("\"hausdorff\": 0,"), std::string::npos);  // the mesh against itself
  const Outcome s = run_scanmesh({"scan", file, path("scan.ply"), "--scan-noise", "0", "--views", "2"}, path("err"), 60.0);
  EXPECT_EQ(s.signal, 0) << "killed: a hang";
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const scanmesh::Mesh scan = scanmesh::read_ply_points(path("scan.ply"));
  ASSERT_GT(scan.num_vertices(), 1000u);
  for (const auto& p : scan.positions) {
    ASSERT_NEAR(p.z(), 0.0, 1e-9);  // every hit on the plane
    ASSERT_GE(p.x(), -1e-9);
    ASSERT_LE(p.x(), n - 1 + 1e-9);
  }
}

TEST_F(Hostile, AFanOfLongThinFacesIsEvaluatedAgainstItself) {
  // 100,000 spokes from one centre to a unit circle: every face is long and thin. eval's closest points
  // came from a k-d tree over face centroids searched within the closest distance plus the longest
  // centroid-to-corner reach, so each query scanned most of the fan (200,000 spokes ran past a minute);
  // the R-tree over face boxes visits the few boxes near each query. 30 s (it takes 0.25 s; 58 s before).
#ifdef SCANMESH_SANITIZED
  const int n = 10000;
#else
  const int n = 100000;
#endif
  scanmesh::Mesh m;
  m.positions.emplace_back(0, 0, 0);
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * i / n;
    m.positions.emplace_back(std::cos(a), std::sin(a), 0.0);
  }
  for (int i = 0; i < n; ++i) m.faces.push_back({0, 1 + i, 1 + (i + 1) % n});
  const std::string file = path("fan.off");
  scanmesh::write_mesh(m, file);
  const Outcome e = run_scanmesh({"eval", file, "--reference", file, "--json", path("eval.json")}, path("err"), 30.0);
  EXPECT_EQ(e.signal, 0) << "killed: a hang";
  EXPECT_EQ(e.exit_code, 0) << e.err;
  EXPECT_NE(scanmesh::read_file(path("eval.json")).find("\"hausdorff\": 0,"), std::string::npos);
}

TEST_F(Hostile, AFewGlitchPointsFarAwayAreOutliersNotALine) {
  // A scanner's glitch: three points at 1e9 beside a 1 x 1 plane. Their spread made the whole cloud read
  // as one line ("no surface to find"), and the box's centre, the origin of the single-precision stages,
  // lay so far from the plane that it would have rounded to one point. Now the glitches are outliers.
  std::string text;
  char line[96];
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      std::snprintf(line, sizeof line, "%.4f %.4f %.5f\n", i / 40.0, j / 40.0, 0.001 * ((i * 7 + j * 13) % 5 - 2));
      text += line;
    }
  text += "1e9 0 0\n1e9 1 0\n-3e8 5 2\n";
  const std::string file = write("glitch.xyz", text);
  const Outcome o = run_scanmesh({"mesh", file, path("out.ply")}, path("err"));
  ASSERT_EQ(o.exit_code, 0) << o.err;
  const scanmesh::Mesh m = scanmesh::read_mesh(path("out.ply"));
  ASSERT_GT(m.num_faces(), 1000u);
  for (const auto& p : m.positions) EXPECT_LT(p.cwiseAbs().maxCoeff(), 2.0);
}

TEST_F(Hostile, ConcurrentRunsWritingOneOutputNeverMix) {
  // Four runs with different voxel sizes write the same .pcd (and sidecar) at once: what is left is
  // exactly one run's complete file, and its sidecar belongs to the same run.
  const std::string cloud = std::string(SCANMESH_DATA_DIR) + "/bun0.pcd";
  const std::vector<std::string> leaves = {"1*spacing", "2*spacing", "3*spacing", "4*spacing"};
  std::vector<std::string> expected;
  for (const auto& leaf : leaves) {
    const std::string yaml = write("p.yaml", "pipeline:\n  - " + cloud + "\n  - type: cloud.voxel\n    voxel_leaf: " + leaf + "\n  - " +
                                                 path("solo.pcd") + "\n");
    ASSERT_EQ(run_scanmesh({"run", yaml, "-q"}, path("err")).exit_code, 0);
    expected.push_back(scanmesh::read_file(path("solo.pcd")));
  }
  for (int round = 0; round < 3; ++round) {
    std::vector<pid_t> pids;
    for (std::size_t k = 0; k < leaves.size(); ++k) {
      const std::string yaml = write("p" + std::to_string(k) + ".yaml", "pipeline:\n  - " + cloud + "\n  - type: cloud.voxel\n    voxel_leaf: " +
                                                                           leaves[k] + "\n  - " + path("same.pcd") + "\n");
      pids.push_back(scanmesh::test::spawn_scanmesh({"run", yaml, "-q"}, path("err" + std::to_string(k))));
    }
    for (std::size_t k = 0; k < pids.size(); ++k)
      EXPECT_EQ(scanmesh::test::wait_scanmesh(pids[k], path("err" + std::to_string(k))).exit_code, 0);
    const std::string got = scanmesh::read_file(path("same.pcd"));
    EXPECT_NE(std::find(expected.begin(), expected.end(), got), expected.end()) << "round " << round << ": a mix of runs";
  }
}

TEST_F(Hostile, AKilledRunIsNotTakenForDone) {
  // A long run killed outright leaves no output, so --skip-existing runs it again instead of skipping.
  const std::string yaml = write("p.yaml", "pipeline:\n  - " + std::string(SCANMESH_DATA_DIR) +
                                               "/fandisk-noisy.obj\n  - type: mesh.denoise\n    iterations: 5000\n  - type: report\n"
                                               "    figures: false\n  - " + path("out.ply") + "\n");
  const pid_t pid = scanmesh::test::spawn_scanmesh({"run", yaml, "-q", "--threads", "1"}, path("err"));
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  ::kill(pid, SIGKILL);
  EXPECT_EQ(scanmesh::test::wait_scanmesh(pid, path("err")).signal, SIGKILL);
  EXPECT_FALSE(fs::exists(path("out.ply")));
  const Outcome again = run_scanmesh({"run", yaml, "--skip-existing", "--set", "mesh.denoise.iterations=2"}, path("err"));
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.err.find("skipped"), std::string::npos) << again.err;
  EXPECT_TRUE(fs::exists(path("out.ply")));
  for (const auto& e : fs::directory_iterator(dir_)) EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

TEST_F(Hostile, RunningOutOfMemoryIsAMessageNotACrash) {
#ifdef SCANMESH_SANITIZED
  GTEST_SKIP() << "the memory guard is off under AddressSanitizer";
#else
  // A 51k-face plane denoised with a radius of 10 c_a (neighbourhoods of ~250 faces) needs ~140 MB of
  // address space; under a 100 MB limit an allocation fails in the neighbourhood search (inside its
  // parallel loop, two threads), which must still end in exit code 1.
  std::string off = "OFF\n" + std::to_string(161 * 161) + " " + std::to_string(2 * 160 * 160) + " 0\n";
  for (int j = 0; j <= 160; ++j)
    for (int i = 0; i <= 160; ++i) off += std::to_string(i) + " " + std::to_string(j) + " " + std::to_string(0.1 * ((i * 7 + j * 13) % 5)) + "\n";
  for (int j = 0; j < 160; ++j)
    for (int i = 0; i < 160; ++i) {
      const int a = j * 161 + i, b = a + 1, c = a + 162, d = a + 161;
      off += "3 " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + "\n3 " + std::to_string(a) + " " +
             std::to_string(c) + " " + std::to_string(d) + "\n";
    }
  const std::string file = write("plane.off", off);
  ::setenv("SCANMESH_MAX_MEMORY_MB", "100", 1);
  const Outcome o = run_scanmesh({"denoise", file, path("out.off"), "--radius-factor", "10", "-q"}, path("err"));
  ::unsetenv("SCANMESH_MAX_MEMORY_MB");
  EXPECT_EQ(o.signal, 0);
  EXPECT_EQ(o.exit_code, 1) << o.err;
  EXPECT_NE(o.err.find("out of memory"), std::string::npos) << o.err;
  EXPECT_FALSE(fs::exists(path("out.off")));
#endif
}
