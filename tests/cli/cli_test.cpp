// End-to-end tests of the scanmesh command line: exit codes, messages, no partial outputs,
// inputs untouched, thread-count independence.
#include <gtest/gtest.h>

#include "scanmesh/pipeline.h"
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "helpers.h"
#include "scanmesh/atomic_file.h"

namespace fs = std::filesystem;

namespace {

struct Result {
  int code = -1;
  std::string out, err;
};

class Cli : public scanmesh::test::TempDirTest {
 protected:
  Result run(const std::string& args) const {
    const std::string cmd = std::string(SCANMESH_BIN) + " " + args + " >" + path("stdout") + " 2>" + path("stderr") + " </dev/null";
    const int status = std::system(cmd.c_str());
    Result r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = scanmesh::read_file(path("stdout"));
    r.err = scanmesh::read_file(path("stderr"));
    return r;
  }
};

const std::string kSample = std::string(SCANMESH_DATA_DIR) + "/fandisk-noisy.obj";
const std::string kReference = std::string(SCANMESH_DATA_DIR) + "/fandisk-clean.obj";

}  // namespace

TEST_F(Cli, BadInputsExitOneWithAMessageAndNoOutput) {
  const std::string ply_header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n";
  std::mt19937 rng(9);
  std::string random_bytes(3000, '\0');
  for (auto& c : random_bytes) c = static_cast<char>(rng());
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"empty.obj", ""},
      {"empty.off", ""},
      {"empty.ply", ""},
      {"truncated.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2"},
      {"truncated.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n"},
      {"truncated.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\nabc"},
      {"nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n"},
      {"nan.off", "OFF\n3 1 0\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n"},
      {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"},
      {"range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"},
      {"noyz.ply", ply_header + "element face 0\nproperty list uchar int vertex_indices\nend_header\n0\n0\n0\n"},
      {"random.stl", random_bytes},
      {"none.stl", std::string(84, '\0')},
      {"unknown.xyz9", "v 0 0 0\n"},
  };
  for (const auto& [name, bytes] : cases) {
    const std::string in = write(name, bytes);
    const std::string out = path("out_" + name + ".ply");
    const Result r = run("denoise " + in + " " + out + " --iterations 2");
    EXPECT_EQ(r.code, 1) << name << ": " << r.err;
    EXPECT_NE(r.err.find(name), std::string::npos) << name << " not named in: " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one message expected: " << r.err;
    EXPECT_FALSE(fs::exists(out)) << name;
    EXPECT_EQ(scanmesh::read_file(in), bytes) << name << " was modified";
  }
  const Result missing = run("denoise " + path("missing.obj") + " " + path("o.ply"));
  EXPECT_EQ(missing.code, 1);
  EXPECT_NE(missing.err.find("missing.obj"), std::string::npos);
  EXPECT_NE(missing.err.find("No such file"), std::string::npos);
}

TEST_F(Cli, BadUsageExitsTwo) {
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
  EXPECT_EQ(run("denoise " + kSample).code, 2);
  EXPECT_EQ(run("denoise " + kSample + " " + path("o.ply") + " --no-such-flag").code, 2);
  Result r = run("denoise " + kSample + " " + path("o.ply") + " --sigma-s 5");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--sigma-s: must be in (0, 2], got 5"), std::string::npos) << r.err;
  r = run("denoise " + kSample + " " + path("o.ply") + " --estimator median");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("tukey"), std::string::npos) << r.err;
  EXPECT_EQ(run("denoise " + kSample + " " + path("o.xyz9")).code, 2);
  EXPECT_EQ(run("denoise " + kSample + " " + path("o.ply") + " --iterations ten").code, 2);
  EXPECT_FALSE(fs::exists(path("o.ply")));
  // The output may never be the input.
  const std::string copy = path("copy.obj");
  fs::copy_file(kSample, copy);
  r = run("denoise " + copy + " " + copy);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("input"), std::string::npos);
  EXPECT_EQ(scanmesh::read_file(copy), scanmesh::read_file(kSample));
}

TEST_F(Cli, ThreadCountDoesNotChangeTheOutput) {
  const Result one = run("denoise " + kSample + " " + path("t1.ply") + " --iterations 20 --threads 1 -q");
  const Result two = run("denoise " + kSample + " " + path("t2.ply") + " --iterations 20 --threads 2 -q");
  ASSERT_EQ(one.code, 0) << one.err;
  ASSERT_EQ(two.code, 0) << two.err;
  EXPECT_EQ(scanmesh::read_file(path("t1.ply")), scanmesh::read_file(path("t2.ply")));
  const Result a1 = run("denoise " + kSample + " " + path("a1.obj") + " --auto --iterations 5 --threads 1 -q");
  const Result a2 = run("denoise " + kSample + " " + path("a2.obj") + " --auto --iterations 5 --threads 2 -q");
  ASSERT_EQ(a1.code, 0) << a1.err;
  EXPECT_EQ(scanmesh::read_file(path("a1.obj")), scanmesh::read_file(path("a2.obj")));
}

TEST_F(Cli, DenoiseThenEvalImprovesTheSample) {
  const std::string before = scanmesh::read_file(kSample);
  Result r = run("denoise " + kSample + " " + path("d.obj") + " --iterations 30");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("[done"), std::string::npos);
  EXPECT_EQ(scanmesh::read_file(kSample), before);
  r = run("eval " + path("d.obj") + " --reference " + kReference + " --json " + path("m.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("MSAE"), std::string::npos);
  const std::string json = scanmesh::read_file(path("m.json"));
  const auto pos = json.find("\"msae_deg\": ");
  ASSERT_NE(pos, std::string::npos);
  EXPECT_LT(std::stod(json.substr(pos + 12)), 5.0);  // the noisy input is at 28 degrees
}

TEST_F(Cli, NoiseIsSeeded) {
  ASSERT_EQ(run("noise " + kReference + " " + path("n1.ply") + " --level 0.3 --seed 4").code, 0);
  ASSERT_EQ(run("noise " + kReference + " " + path("n2.ply") + " --level 0.3 --seed 4").code, 0);
  ASSERT_EQ(run("noise " + kReference + " " + path("n3.ply") + " --level 0.3 --seed 5").code, 0);
  EXPECT_EQ(scanmesh::read_file(path("n1.ply")), scanmesh::read_file(path("n2.ply")));
  EXPECT_NE(scanmesh::read_file(path("n1.ply")), scanmesh::read_file(path("n3.ply")));
  EXPECT_EQ(run("noise " + kReference + " " + path("n4.ply") + " --kind pink").code, 2);
}

TEST_F(Cli, MeshesACloudAndRejectsBadClouds) {
  Result r = run("mesh " + std::string(SCANMESH_DATA_DIR) + "/bun0.pcd " + path("bun.ply"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("397 points"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("boundary loops"), std::string::npos) << r.err;
  const std::string header = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 100\nHEIGHT 1\nPOINTS 100\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"empty.pcd", ""},
      {"allnan.xyz", "nan nan nan\nnan nan nan\n"},
      {"header.pcd", "HELLO\n" + header + "DATA ascii\n"},
      {"truncated.pcd", header + "DATA binary\n" + std::string(64, '\0')},
  };
  for (const auto& [name, bytes] : cases) {
    const std::string in = write(name, bytes);
    const std::string out = path("out_" + name + ".ply");
    r = run("mesh " + in + " " + out);
    EXPECT_EQ(r.code, 1) << name << ": " << r.err;
    EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
  EXPECT_EQ(run("mesh " + std::string(SCANMESH_DATA_DIR) + "/bun0.pcd " + path("x.ply") + " --method magic").code, 2);
  EXPECT_EQ(run("mesh " + std::string(SCANMESH_DATA_DIR) + "/bun0.pcd " + path("x.ply") + " --gp3-radius far").code, 2);
}

TEST_F(Cli, PipelineMatchesTheSubcommandsAndWritesAReport) {
  const std::string config = std::string(SCANMESH_DATA_DIR) + "/../configs/scan_to_mesh.yaml";
  const std::string scan = std::string(SCANMESH_DATA_DIR) + "/bun0.pcd";
  Result r = run("run " + config + " --input " + scan + " --output " + path("p.ply") + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(run("mesh " + scan + " " + path("m.ply") + " -q").code, 0);
  // The main job marks the meshes it makes as scanned (mesh.denoise's `scanned`), and greedy projection's,
  // whose vertices are the points, as such (`vertices_are_points`).
  ASSERT_EQ(run("denoise " + path("m.ply") + " " + path("d.ply") + " --auto --scanned --vertices-are-points -q").code, 0);
  EXPECT_EQ(scanmesh::read_file(path("p.ply")), scanmesh::read_file(path("d.ply")));
  EXPECT_NE(scanmesh::read_file(path("p.report.json")).find("\"status\": \"ok\""), std::string::npos);
  EXPECT_TRUE(fs::exists(path("p.report.html")));
  // --validate checks without running; --skip-existing leaves a finished output alone.
  r = run("run " + config + " --input " + scan + " --output " + path("v.ply") + " --validate");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(path("v.ply")));
  const auto before = fs::last_write_time(path("p.ply"));
  r = run("run " + config + " --input " + scan + " --output " + path("p.ply") + " --skip-existing");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.err.find("skipped"), std::string::npos) << r.err;
  EXPECT_EQ(fs::last_write_time(path("p.ply")), before);
  // A bad configuration is a usage error naming FILE:LINE.
  const std::string bad = write("bad.yaml", "pipeline:\n  - " + scan + "\n  - type: cloud.normalz\n  - " + path("b.ply") + "\n");
  r = run("run " + bad);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find(bad + ":3:"), std::string::npos) << r.err;
  r = run("run " + config + " --set mesh.gp3_radiuss=3*spacing");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("did you mean 'gp3_radius'"), std::string::npos) << r.err;
}

namespace {

std::string squeeze(const std::string& text) {  // whitespace runs as one space (help text is wrapped)
  std::string out;
  for (char c : text) {
    const bool space = c == ' ' || c == '\n' || c == '\t';
    if (space && (out.empty() || out.back() == ' ')) continue;
    out += space ? ' ' : c;
  }
  return out;
}

}  // namespace

TEST_F(Cli, EveryVerbsHelpIsItsStagesSchema) {
  // The flags, defaults, ranges and texts of `scanmesh VERB --help` against the options structs' schemas:
  // a default, range or doc changed in one place and not the other fails here.
  scanmesh::register_scan_stages();
  const std::vector<std::pair<std::string, std::vector<std::string>>> verbs = {
      {"denoise", {"mesh.denoise", "write"}},
      {"noise", {"mesh.noise", "write"}},
      {"mesh", {"read", "cloud.dequantize", "cloud.voxel", "cloud.outliers", "cloud.normals", "mesh.auto", "mesh.cleanup", "write"}},
      {"scan", {"scan.virtual", "write"}}};
  for (const auto& [verb, stages] : verbs) {
    const Result r = run(verb + " --help");
    ASSERT_EQ(r.code, 0) << verb;
    const std::string help = squeeze(r.out);
    std::size_t checked = 0;
    for (const auto& type : stages)
      for (const auto& o : scanmesh::stage_options(type)) {
        if (o.info.name == "filename") continue;
        const std::string flag = o.info.flag();
        EXPECT_NE(help.find(flag), std::string::npos) << verb << ": " << flag;
        EXPECT_NE(help.find(squeeze(o.info.doc + " [" + o.info.domain() + "; default " + o.default_value + "]")), std::string::npos)
            << verb << " " << flag << ": doc, range or default differ from the schema";
        ++checked;
      }
    EXPECT_GT(checked, 0u) << verb;
  }
}

TEST_F(Cli, TheReadmeOptionTablesAreTheSchema) {
  const Result r = run("options --markdown");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string readme = scanmesh::read_file(std::string(SCANMESH_DATA_DIR) + "/../README.md");
  const std::string begin = "<!-- options:begin (scanmesh options --markdown) -->\n", end = "<!-- options:end -->";
  const std::size_t a = readme.find(begin), b = readme.find(end);
  ASSERT_NE(a, std::string::npos);
  ASSERT_NE(b, std::string::npos);
  EXPECT_EQ(readme.substr(a + begin.size(), b - a - begin.size()), r.out)
      << "README.md's options tables differ from the schemas; regenerate them with build/bin/scanmesh options --markdown";
}

TEST_F(Cli, RunAndTheVerbsPrintTheSameWarnings) {
  // A reader's warning reaches the terminal through `run` as through a verb, and the sidecar; -q hides it
  // from the terminal only.
  const std::string mesh = write("collapsed.off", "OFF\n5 4 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0.1\n0.5 0.5 0.2\n3 0 1 4\n3 1 3 4\n"
                                                  "3 3 2 4\n3 2 2 4\n");
  const std::string needle = "collapsed.off: 1 face names a vertex twice (first: face 3, vertices 2 2 4)";
  const std::string config = std::string(SCANMESH_DATA_DIR) + "/../configs/denoise.yaml";
  const Result p = run("run " + config + " --input " + mesh + " --output " + path("p.off"));
  const Result v = run("denoise " + mesh + " " + path("v.off"));
  const Result q = run("run " + config + " --input " + mesh + " --output " + path("q.off") + " -q");
  ASSERT_EQ(p.code, 0) << p.err;
  ASSERT_EQ(v.code, 0) << v.err;
  ASSERT_EQ(q.code, 0) << q.err;
  EXPECT_NE(p.err.find("warning: " + mesh + ": 1 face names"), std::string::npos) << p.err;
  EXPECT_NE(v.err.find(needle), std::string::npos) << v.err;
  EXPECT_EQ(q.err.find(needle), std::string::npos) << q.err;
  EXPECT_NE(scanmesh::read_file(path("q.report.json")).find(needle), std::string::npos);
}

TEST_F(Cli, ACloudThatMeshesToNothingFailsAlikeInMeshAndRun) {
  const std::string cloud = write("six.xyz", "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0.5 0.5 3\n9 9 9\n");
  const Result m = run("mesh " + cloud + " " + path("m.ply"));
  const std::string config = std::string(SCANMESH_DATA_DIR) + "/../configs/scan_to_mesh.yaml";
  const Result p = run("run " + config + " --input " + cloud + " --output " + path("p.ply"));
  EXPECT_EQ(m.code, 1) << m.err;
  EXPECT_EQ(p.code, 1) << p.err;
  // One check, one message: the same reason through both, the command line's naming the file.
  const std::string reason = "meshing produced no triangles (too few points, or try a larger gp3_radius)";
  EXPECT_NE(m.err.find(cloud + ": mesh.auto: " + reason), std::string::npos) << m.err;
  EXPECT_NE(p.err.find(reason), std::string::npos) << p.err;
  EXPECT_FALSE(fs::exists(path("m.ply")));
  EXPECT_FALSE(fs::exists(path("p.ply")));
  EXPECT_NE(scanmesh::read_file(path("p.report.json")).find("\"status\": \"failed\""), std::string::npos);
}

TEST_F(Cli, HelpExplainsEveryParameter) {
  const Result r = run("denoise --help");
  EXPECT_EQ(r.code, 0);
  for (const char* word : {"--sigma-s", "--lambda", "--iterations", "--auto", "--threads", "--estimator",
                           "--neighbourhood", "--radius-factor", "--decay"})
    EXPECT_NE(r.out.find(word), std::string::npos) << word;
  EXPECT_EQ(run("eval --help").code, 0);
  EXPECT_EQ(run("noise --help").code, 0);
}

TEST_F(Cli, EvalSaysWhichFacesItsQualityLeavesOut) {
  // Two right triangles and one whose corners coincide: Q is the mean over the two, and eval says the third
  // was left out instead of averaging silently over fewer faces.
  const std::string off = write("m.off", "OFF\n7 3 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n5 5 5\n5 5 5\n5 5 5\n3 0 1 2\n3 1 3 2\n3 4 5 6\n");
  Result r = run("eval " + off);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("over 2 faces; 1 without a finite Q"), std::string::npos) << r.out;
  const std::string bad = write("d.off", "OFF\n3 1 0\n5 5 5\n5 5 5\n5 5 5\n3 0 1 2\n");
  r = run("eval " + bad);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("Q:          none"), std::string::npos) << r.out;
}
