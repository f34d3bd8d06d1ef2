#include "scanmesh/pipeline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <mutex>

#include "helpers.h"
#include "scanmesh/add_noise.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/auto_denoise.h"
#include "scanmesh/denoise.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/report.h"

using namespace scanmesh;
namespace fs = std::filesystem;

namespace {

// Every stage family, as the full command-line tool has them.
const bool kRegistered = (register_scan_stages(), true);

class PipelineTest : public test::TempDirTest {
 protected:
  void SetUp() override {
    ASSERT_TRUE(kRegistered);
    TempDirTest::SetUp();
    Mesh m = test::make_sphere(3);
    for (std::size_t v = 0; v < m.num_vertices(); v += 3) m.positions[v] *= 1.01;  // a little noise
    write_mesh(m, path("in.ply"));
  }
  // Loads a pipeline text and expects a ConfigError mentioning FILE:LINE and `needle`.
  void expect_config_error(const std::string& yaml, int line, const std::string& needle) {
    const std::string file = write("p.yaml", yaml);
    try {
      Pipeline::load(file, {});
      ADD_FAILURE() << "no error for:\n" << yaml;
    } catch (const ConfigError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(file + ":" + std::to_string(line) + ":"), std::string::npos) << msg;
      EXPECT_NE(msg.find(needle), std::string::npos) << "'" << needle << "' not in: " << msg;
    }
    EXPECT_FALSE(fs::exists(path("out.ply")));
  }
};

}  // namespace

// One test per kind of configuration error; each must stop before anything runs (no output file).
TEST_F(PipelineTest, YamlSyntaxError) {
  // yaml-cpp notices the unclosed bracket at the end of the document.
  expect_config_error("pipeline:\n  - " + path("in.ply") + "\n  - type: mesh.denoise\n    sigma_s: [0.5\n", 5, "YAML syntax error");
}

TEST_F(PipelineTest, UnknownStageType) {
  expect_config_error("pipeline:\n  - " + path("in.ply") + "\n  - type: mesh.denoize\n  - " + path("out.ply") + "\n", 3,
                      "did you mean 'mesh.denoise'");
}

TEST_F(PipelineTest, UnknownKey) {
  expect_config_error("pipeline:\n  - " + path("in.ply") + "\n  - type: mesh.denoise\n    sigma: 0.5\n  - " + path("out.ply") + "\n", 4,
                      "unknown option 'sigma'; did you mean 'sigma_s'");
}

TEST_F(PipelineTest, WrongValueType) {
  expect_config_error("pipeline:\n  - " + path("in.ply") + "\n  - type: mesh.denoise\n    iterations: many\n  - " + path("out.ply") + "\n", 4,
                      "key 'iterations': expected a whole number");
  expect_config_error("pipeline:\n  - " + path("in.ply") + "\n  - type: mesh.denoise\n    estimator: median\n  - " + path("out.ply") + "\n", 4,
                      "choose tukey | gaussian | huber | lorentzian");
}

TEST_F(PipelineTest, MissingInputFile) {
  expect_config_error("pipeline:\n  - " + path("missing.ply") + "\n  - type: mesh.denoise\n  - " + path("out.ply") + "\n", 2, "No such file");
}

TEST_F(PipelineTest, UnknownTagInInputs) {
  expect_config_error("pipeline:\n  - " + path("in.ply") + "\n  - type: mesh.denoise\n    tag: smooth\n  - type: mesh.cleanup\n    inputs: [smoth]\n  - " +
                          path("out.ply") + "\n",
                      6, "no earlier stage has the tag 'smoth'; did you mean 'smooth'");
}

TEST_F(PipelineTest, RunsWritesAReportAndMatchesTheApi) {
  const std::string yaml = "pipeline:\n  - " + path("in.ply") +
                           "\n  - type: mesh.denoise\n    tag: d\n    iterations: 10\n  - type: report\n  - " + path("out.ply") + "\n";
  Pipeline p = Pipeline::load(write("p.yaml", yaml), {});
  const PipelineResult r = p.run();
  ASSERT_TRUE(fs::exists(path("out.ply")));
  const ReportPaths rp = report_paths(path("out.ply"));
  const std::string json = read_file(rp.json);
  EXPECT_NE(json.find("\"status\": \"ok\""), std::string::npos);
  EXPECT_NE(json.find("\"stages\""), std::string::npos);
  EXPECT_NE(json.find("triangle_quality"), std::string::npos);
  EXPECT_TRUE(fs::exists(rp.html));
  std::size_t pngs = 0;
  for (const auto& e : fs::directory_iterator(rp.folder)) pngs += e.path().extension() == ".png" ? 1 : 0;
  EXPECT_GE(pngs, 3u);
  // The same through the C++ API gives the same bytes.
  Mesh m = read_mesh(path("in.ply"));
  DenoiseOptions o;
  o.iterations = 10;
  denoise(m, o);
  write_mesh(m, path("api.ply"));
  EXPECT_EQ(read_file(path("api.ply")), read_file(path("out.ply")));
}

// A file read twice (the input, then the report's reference) warns once, on the terminal and in the sidecar.
TEST_F(PipelineTest, AWarningIsGivenOnce) {
  std::string obj;
  const Mesh sphere = test::make_sphere(2);
  for (const Vec3& p : sphere.positions) obj += "v " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\nvt 0 0\n";
  for (const Face& f : sphere.faces) obj += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + "\n";
  const std::string in = write("uv.obj", obj);
  const std::string yaml = "pipeline:\n  - " + in + "\n  - type: mesh.denoise\n    iterations: 2\n  - type: report\n    reference: " + in +
                           "\n  - " + path("out.ply") + "\n";
  const PipelineResult r = Pipeline::load(write("p.yaml", yaml), {}).run();
  const auto about_uv = std::count_if(r.warnings.begin(), r.warnings.end(), [](const std::string& w) { return w.find("(vt/vn)") != std::string::npos; });
  EXPECT_EQ(about_uv, 1);
  const std::string json = read_file(report_paths(path("out.ply")).json);
  const std::size_t first = json.find("(vt/vn)");
  ASSERT_NE(first, std::string::npos);
  EXPECT_EQ(json.find("(vt/vn)", first + 1), std::string::npos);
}

// What --auto measured and chose is in the sidecar as named values and in the HTML page, and matches the
// API's AutoReport for the same mesh.
TEST_F(PipelineTest, TheAutoDecisionIsInTheSidecarAndThePage) {
  const std::string yaml = "pipeline:\n  - " + path("in.ply") + "\n  - type: mesh.denoise\n    auto: true\n  - type: report\n  - " +
                           path("out.ply") + "\n";
  Pipeline::load(write("p.yaml", yaml), {}).run();
  const ReportPaths rp = report_paths(path("out.ply"));
  const std::string json = read_file(rp.json), html = read_file(rp.html);
  Mesh m = read_mesh(path("in.ply"));
  const AutoReport a = denoise_auto(m, DenoiseOptions{});
  ASSERT_FALSE(a.mode.empty());
  const std::size_t decision = json.find("\"decision\": {");
  ASSERT_NE(decision, std::string::npos) << json;
  EXPECT_NE(json.find("\"mode\": \"" + a.mode + "\"", decision), std::string::npos) << json;
  for (const char* key : {"\"noise_level\": ", "\"soft_crease_share\": ", "\"stop_reason\": ", "\"check\": ", "\"boundary_loops_stopped\": "})
    EXPECT_NE(json.find(key), std::string::npos) << key;
  EXPECT_NE(json.find("\"scanned\": \"false\"", decision), std::string::npos) << json;  // a mesh file, not made here
  // A share the run did not measure (here: no flat-edge shares, the run ends before the probe) is left
  // out, never written as -1.
  ASSERT_LT(a.flat_share, 0.0) << a.reason;
  for (const char* key : {"\"soft_crease_share\": -", "\"flat_edge_share\": -", "\"flat_edge_share_half_probe\": -"})
    EXPECT_EQ(json.find(key), std::string::npos) << key;
  EXPECT_NE(html.find("Decision of mesh.denoise"), std::string::npos);
  EXPECT_EQ(read_file(path("out.ply")), [&] {
    write_mesh(m, path("api.ply"));
    return read_file(path("api.ply"));
  }());
}

// After a voxel grid thins the cloud, lengths in spacings mean the new spacing: greedy projection's
// 5 x spacing would be under the thinned cloud's spacing if it were the input's, and mesh nothing.
TEST_F(PipelineTest, LengthsAfterAVoxelGridAreInItsSpacing) {
  std::string xyz;
  for (int j = 0; j < 60; ++j)
    for (int i = 0; i < 60; ++i) xyz += std::to_string(0.01 * i) + " " + std::to_string(0.01 * j) + " 0\n";
  write("c.xyz", xyz);
  const std::string yaml = "pipeline:\n  - " + path("c.xyz") + "\n  - type: cloud.voxel\n    voxel_max_points: 100\n  - type: cloud.normals\n"
                           "  - type: mesh.gp3\n  - " + path("out.ply") + "\n";
  Pipeline::load(write("p.yaml", yaml), {}).run();
  const Mesh m = read_mesh(path("out.ply"));
  EXPECT_LE(m.num_vertices(), 100u);
  EXPECT_GE(m.faces.size(), 100u);
  for (const Vec3& p : m.positions) EXPECT_EQ(p.z(), 0.0);
}

TEST_F(PipelineTest, OverridesReplaceInputOutputAndOptions) {
  const std::string yaml = "pipeline:\n  - " + path("nothing.ply") + "\n  - type: mesh.denoise\n    tag: d\n  - " + path("x.ply") + "\n";
  PipelineOptions o;
  o.input = path("in.ply");
  o.output = path("out.ply");
  o.sets = {"d.iterations=3", "d.sigma_s=0.5"};
  Pipeline p = Pipeline::load(write("p.yaml", yaml), o);
  EXPECT_EQ(p.output(), path("out.ply"));
  EXPECT_NE(p.resolved_config().find("iterations: 3"), std::string::npos) << p.resolved_config();
  p.run();
  EXPECT_TRUE(fs::exists(path("out.ply")));
  o.sets = {"nosuchtag.iterations=3"};
  EXPECT_THROW(Pipeline::load(path("p.yaml"), o), ConfigError);
  o.sets = {"d.iterations=lots"};
  EXPECT_THROW(Pipeline::load(path("p.yaml"), o), ConfigError);
}

TEST_F(PipelineTest, BareListAndInputsTakeDataFromATaggedStage) {
  // A bare list (no 'pipeline:' key); the cleanup takes the noisy mesh, skipping the denoiser's output.
  const std::string yaml = "- " + path("in.ply") + "\n- type: mesh.noise\n  tag: noisy\n  level: 0.5\n- type: mesh.denoise\n  iterations: 20\n"
                           "- type: mesh.cleanup\n  inputs: noisy\n- " + path("out.ply") + "\n";
  Pipeline::load(write("p.yaml", yaml), {}).run();
  Mesh noisy = read_mesh(path("in.ply"));
  NoiseOptions n;
  n.level = 0.5;
  add_noise(noisy, n);
  const Mesh out = read_mesh(path("out.ply"));
  EXPECT_EQ(out.positions, noisy.positions);  // the denoised branch was not used
}

TEST_F(PipelineTest, AFailingRunLeavesAFailedSidecarAndNoOutput) {
  // Organized meshing needs an organized cloud: the run fails on the data (not the configuration).
  write("c.xyz", "0 0 0\n1 0 0\n0 1 0\n1 1 0\n");
  const std::string yaml = "pipeline:\n  - " + path("c.xyz") + "\n  - type: mesh.organized\n  - type: report\n  - " + path("out.ply") + "\n";
  Pipeline p = Pipeline::load(write("p.yaml", yaml), {});
  EXPECT_THROW(p.run(), Error);
  EXPECT_FALSE(fs::exists(path("out.ply")));
  const std::string json = read_file(report_paths(path("out.ply")).json);
  EXPECT_NE(json.find("\"status\": \"failed\""), std::string::npos) << json;
  EXPECT_NE(json.find("mesh.organized"), std::string::npos) << json;
}

TEST_F(PipelineTest, AMeshGivenToCloudStagesOrACloudToMeshStagesIsNamedWithWhatToDo) {
  // The main job given a mesh file (a scanner's own mesh, say) and a denoising pipeline given a cloud: the
  // error says what the input is and which command fits it, not only that a stage lacks its data.
  auto run_error = [&](const std::string& yaml) {
    Pipeline p = Pipeline::load(write("p.yaml", yaml), {});
    try {
      p.run();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string on_mesh = run_error("pipeline:\n  - " + path("in.ply") + "\n  - type: cloud.outliers\n  - " + path("out.ply") + "\n");
  EXPECT_NE(on_mesh.find("needs a point cloud, but the input is a triangle mesh (1280 faces)"), std::string::npos) << on_mesh;
  EXPECT_NE(on_mesh.find("scanmesh denoise"), std::string::npos) << on_mesh;
  write("c.xyz", "0 0 0\n1 0 0\n0 1 0\n1 1 0\n");
  const std::string on_cloud = run_error("pipeline:\n  - " + path("c.xyz") + "\n  - type: mesh.denoise\n  - " + path("out.ply") + "\n");
  EXPECT_NE(on_cloud.find("mesh.denoise needs a triangle mesh, but the input is a point cloud (4 points)"), std::string::npos) << on_cloud;
  EXPECT_NE(on_cloud.find("scanmesh mesh"), std::string::npos) << on_cloud;
  EXPECT_FALSE(fs::exists(path("out.ply")));
}

TEST_F(PipelineTest, AFailureAfterAWriterLeavesNoOutputOfThatWriter) {
  // Outputs are committed only when the whole run succeeds; the intermediate writer's file never appears.
  const std::string yaml = "pipeline:\n  - " + path("in.ply") + "\n  - type: write\n    filename: " + path("mid.ply") +
                           "\n  - type: cloud.voxel\n  - " + path("out.ply") + "\n";
  Pipeline p = Pipeline::load(write("p.yaml", yaml), {});
  EXPECT_THROW(p.run(), Error);
  EXPECT_FALSE(fs::exists(path("mid.ply")));
  EXPECT_FALSE(fs::exists(path("out.ply")));
  for (const auto& e : fs::directory_iterator(dir_)) EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

TEST_F(PipelineTest, NoWriterMayOverwriteAnInput) {
  expect_config_error("pipeline:\n  - " + path("in.ply") + "\n  - type: write\n    filename: " + path("in.ply") +
                          "\n  - type: mesh.denoise\n  - " + path("out.ply") + "\n",
                      3, "is an input of this pipeline");
}

TEST_F(PipelineTest, AMissingOutputFolderFailsAtLoading) {
  expect_config_error("pipeline:\n  - " + path("in.ply") + "\n  - type: mesh.denoise\n  - " + path("no/such/folder/out.ply") + "\n", 4,
                      "does not exist");
}

TEST_F(PipelineTest, AnEmptyResultIsAFailure) {
  // Cropping every point away: nothing to write is an error, with a failed sidecar, not an empty file.
  write("c.xyz", "0 0 0\n1 0 0\n0 1 0\n1 1 0\n");
  const std::string yaml = "pipeline:\n  - " + path("c.xyz") + "\n  - type: cloud.crop\n    crop_min: [5, 5, 5]\n  - type: report\n  - " +
                           path("out.ply") + "\n";
  Pipeline p = Pipeline::load(write("p.yaml", yaml), {});
  EXPECT_THROW(p.run(), Error);
  EXPECT_FALSE(fs::exists(path("out.ply")));
  EXPECT_NE(read_file(report_paths(path("out.ply")).json).find("\"status\": \"failed\""), std::string::npos);
}

TEST(PipelineSchema, EveryStageTypeIsListed) {
  ASSERT_TRUE(kRegistered);
  const auto schema = pipeline_schema();
  std::vector<std::string> types;
  for (const auto& [t, keys] : schema) types.push_back(t);
  for (const char* t : {"cloud.crop", "cloud.voxel", "cloud.outliers", "cloud.normals", "cloud.mls", "mesh.gp3", "mesh.organized",
                        "mesh.poisson", "mesh.cleanup", "mesh.denoise", "mesh.noise", "scan.virtual", "report"})
    EXPECT_NE(std::find(types.begin(), types.end(), t), types.end()) << t;
  for (const auto& [t, keys] : schema) {
    if (t != "mesh.denoise") continue;
    for (const char* k : {"sigma_s", "lambda", "iterations", "auto"}) EXPECT_NE(std::find(keys.begin(), keys.end(), k), keys.end()) << k;
  }
}

TEST_F(PipelineTest, AMeshThatLeavesItsScanOutIsDegradedNotOk) {
  // A flat patch of 400 points and 40 stray points far above it: no surface reaches the strays, so the
  // mesh leaves 9% of the points out. The result is written, but its status says so, with the reason.
  std::string patch;
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) patch += std::to_string(i * 0.01) + " " + std::to_string(j * 0.01) + " 0\n";
  std::string xyz = patch;
  for (int k = 0; k < 40; ++k) xyz += std::to_string(0.005 * k) + " " + std::to_string(0.1 + 0.003 * (k % 7)) + " " + std::to_string(0.5 + 0.02 * k) + "\n";
  write("c.xyz", xyz);
  const std::string yaml = "pipeline:\n  - " + path("c.xyz") + "\n  - type: cloud.normals\n  - type: mesh.auto\n  - type: mesh.cleanup\n  - type: report\n    figures: false\n  - " +
                           path("out.ply") + "\n";
  const PipelineResult r = Pipeline::load(write("p.yaml", yaml), {}).run();
  EXPECT_EQ(r.status, "degraded");
  ASSERT_FALSE(r.problems.empty());
  EXPECT_NE(r.problems[0].find("leaves"), std::string::npos) << r.problems[0];
  EXPECT_TRUE(fs::exists(path("out.ply")));
  const std::string json = read_file(report_paths(path("out.ply")).json);
  EXPECT_NE(json.find("\"status\": \"degraded\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"scan_fit\": {"), std::string::npos);
  // A patch that meshes completely is ok.
  write("good.xyz", patch);
  const std::string good = "pipeline:\n  - " + path("good.xyz") + "\n  - type: cloud.normals\n  - type: mesh.auto\n  - type: mesh.cleanup\n  - " + path("good.ply") + "\n";
  EXPECT_EQ(Pipeline::load(write("g.yaml", good), {}).run().status, "ok");
}

// A mesh the pipeline triangulated from a cloud is denoised as a scanned mesh (every vertex noisy, no
// impulsive mode), unless the configuration says otherwise.
TEST_F(PipelineTest, AMeshMadeFromACloudIsDenoisedAsAScannedMesh) {
  std::string xyz;
  for (int j = 0; j < 30; ++j)
    for (int i = 0; i < 30; ++i) xyz += std::to_string(i * 0.01) + " " + std::to_string(j * 0.01) + " " + std::to_string(0.001 * ((i * 7 + j * 3) % 5 - 2)) + "\n";
  write("c.xyz", xyz);
  // "scanned/vertices_are_points" as the sidecar gives them.
  auto scanned_in_sidecar = [&](const std::string& denoise_keys, const std::string& before_denoise = "",
                                const std::string& method = "mesh.gp3") {
    const std::string yaml = "pipeline:\n  - " + path("c.xyz") + "\n  - type: cloud.normals\n  - type: " + method + "\n  - type: mesh.cleanup\n" +
                             before_denoise + "  - type: mesh.denoise\n    auto: true\n" + denoise_keys + "  - type: report\n    figures: false\n  - " +
                             path("out.ply") + "\n";
    Pipeline::load(write("p.yaml", yaml), {}).run();
    const std::string json = read_file(report_paths(path("out.ply")).json);
    std::string flags;
    const std::size_t decision = json.find("\"decision\"", json.find("\"mesh.denoise\""));
    for (const char* key : {"scanned", "vertices_are_points"}) {
      const std::string k = std::string("\"") + key + "\": \"";
      const std::size_t at = json.find(k, decision);
      if (at == std::string::npos) return json;
      flags += (flags.empty() ? "" : "/") + json.substr(at + k.size(), json.find('"', at + k.size()) - at - k.size());
    }
    return flags;
  };
  EXPECT_EQ(scanned_in_sidecar(""), "true/true");  // greedy projection: the points are the vertices
  EXPECT_EQ(scanned_in_sidecar("    scanned: false\n"), "false/false");  // no scan, so no scan's points either
  EXPECT_EQ(scanned_in_sidecar("    vertices_are_points: false\n"), "true/false");
  // Poisson's vertices are a surface fitted to the points: scanned, but its triangles are its own.
  EXPECT_EQ(scanned_in_sidecar("", "", "mesh.poisson"), "true/false");
  // Synthetic noise added after meshing is not the scanner's: impulsive noise must stay possible.
  EXPECT_EQ(scanned_in_sidecar("", "  - type: mesh.noise\n    kind: impulsive\n"), "false/false");
  // Without auto the option changes nothing, and the run says so.
  const std::string plain = "pipeline:\n  - " + path("in.ply") + "\n  - type: mesh.denoise\n    iterations: 2\n    scanned: true\n  - " + path("p.ply") + "\n";
  const PipelineResult r = Pipeline::load(write("plain.yaml", plain), {}).run();
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("without auto it has no effect"), std::string::npos) << r.warnings[0];
}

// A stage without progress lines of its own says it is still running while it runs; stages with their
// own progress (meshing, denoising) stay quiet; heartbeat_seconds = 0 turns it off.
TEST_F(PipelineTest, LongStagesWithoutProgressSayTheyAreStillRunning) {
  std::string xyz;
  for (int j = 0; j < 120; ++j)
    for (int i = 0; i < 120; ++i)
      xyz += std::to_string(i * 0.01) + " " + std::to_string(j * 0.01) + " " + std::to_string(0.02 * std::sin(0.1 * i + 0.2 * j)) + "\n";
  write("c.xyz", xyz);
  const std::string yaml = "pipeline:\n  - " + path("c.xyz") + "\n  - type: cloud.normals\n  - type: mesh.auto\n  - type: mesh.denoise\n    iterations: 20\n  - " +
                           path("out.ply") + "\n";
  auto lines_of = [&](double period) {
    std::mutex m;
    std::vector<std::string> lines;
    PipelineOptions o;
    o.heartbeat_seconds = period;
    o.log = [&](const std::string& line) {
      const std::lock_guard<std::mutex> lock(m);
      lines.push_back(line);
    };
    Pipeline::load(write("p.yaml", yaml), o).run();
    std::vector<std::string> still;
    for (const auto& l : lines)
      if (l.find("still running") != std::string::npos) still.push_back(l);
    return still;
  };
  const std::vector<std::string> still = lines_of(0.0005);  // 14,400 normals take far longer than this
  ASSERT_FALSE(still.empty());
  bool normals = false;
  for (const auto& l : still) {
    normals = normals || l.rfind("cloud.normals: still running (", 0) == 0;
    EXPECT_EQ(l.find("mesh.denoise"), std::string::npos) << l;
    EXPECT_EQ(l.find("mesh.auto"), std::string::npos) << l;
  }
  EXPECT_TRUE(normals);
  EXPECT_TRUE(lines_of(0.0).empty());
}

// A result that shrank does not leave silently: the zippered cylinder under weak noise (see
// AutoDenoise.AResultThatShrankIsReported) gets a warning naming the move and the volume change, and the
// sidecar's decision has both numbers. A sphere under the same zero-mean noise gets no such warning. (The
// fixture's sphere would: its "noise" moves a third of the vertices outwards only, so removing it moves
// the surface inwards, which the measure, made for zero-mean scanner noise, reads as shrinkage.)
TEST_F(PipelineTest, AResultThatShrankIsAWarning) {
  Mesh m = test::make_zippered_cylinder();
  NoiseOptions n;
  n.level = 0.1;
  add_noise(m, n);
  write_mesh(m, path("cyl.ply"));
  auto run = [&](const std::string& input) {
    const std::string yaml = "pipeline:\n  - " + path(input) + "\n  - type: mesh.denoise\n    auto: true\n  - type: report\n    figures: false\n  - " +
                             path("out.ply") + "\n";
    return Pipeline::load(write("p.yaml", yaml), {}).run();
  };
  const PipelineResult shrank = run("cyl.ply");
  const auto w = std::find_if(shrank.warnings.begin(), shrank.warnings.end(), [](const std::string& s) { return s.find("shrank") != std::string::npos; });
  ASSERT_NE(w, shrank.warnings.end());
  EXPECT_NE(w->find("volume changed by -"), std::string::npos) << *w;
  const std::string json = read_file(report_paths(path("out.ply")).json);
  EXPECT_NE(json.find("\"mean_normal_move\": -"), std::string::npos) << json;
  EXPECT_NE(json.find("\"volume_change\": -"), std::string::npos) << json;
  EXPECT_NE(json.find("shrank"), std::string::npos);  // the warning is in the sidecar too
  Mesh sphere_mesh = test::make_sphere(4);
  add_noise(sphere_mesh, n);
  write_mesh(sphere_mesh, path("sphere.ply"));
  const PipelineResult sphere = run("sphere.ply");
  for (const auto& s : sphere.warnings) EXPECT_EQ(s.find("on average"), std::string::npos) << s;
}

TEST(ReportViews, FrameTheObjectsPiecesButNotOutliers) {
  // A sphere (the main piece), a small sphere just beside it (a part a scan left apart) and one far away
  // (an outlying fragment): the views frame the first two.
  Mesh m = test::make_sphere(3);
  const std::size_t main_vertices = m.num_vertices();
  auto add_piece = [&m](const Vec3& at, double size) {
    const Mesh s = test::make_sphere(1);
    const auto base = static_cast<int>(m.num_vertices());
    for (const Vec3& p : s.positions) m.positions.push_back(at + size * p);
    for (const Face& f : s.faces) m.faces.push_back({f[0] + base, f[1] + base, f[2] + base});
    return s.num_vertices();
  };
  const std::size_t near = add_piece(Vec3(1.3, 0, 0), 0.2);
  add_piece(Vec3(40, 0, 0), 0.2);
  const std::vector<int> framed = framed_vertices(m);
  ASSERT_EQ(framed.size(), main_vertices + near);
  for (int v : framed) EXPECT_LT(m.positions[v].x(), 2.0);
  // A lone piece is framed whole; a vertex at infinity is left out.
  m = test::make_sphere(2);
  m.positions.push_back(Vec3(std::numeric_limits<double>::infinity(), 0, 0));
  EXPECT_EQ(framed_vertices(m).size(), m.num_vertices() - 1);
}
