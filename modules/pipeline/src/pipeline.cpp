#include "scanmesh/pipeline.h"

#include <sys/resource.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <memory>

#include "binder.h"
#include "scanmesh/add_noise.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/clean_cloud.h"
#include "scanmesh/clean_mesh.h"
#include "scanmesh/cloud_io.h"
#include "scanmesh/denoise.h"
#include "scanmesh/auto_denoise.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/parallel.h"
#include "scanmesh/report.h"
#include "scanmesh/triangulate.h"
#include "scanmesh/virtual_scan.h"

#ifndef SCANMESH_VERSION
#define SCANMESH_VERSION "unknown"
#endif

namespace scanmesh {
namespace {

using detail::Binder;
using detail::Where;

// What flows from stage to stage.
struct Data {
  std::optional<PointCloud> cloud;
  std::optional<Mesh> mesh;
  std::optional<Mesh> before;  // the mesh before the first vertex-moving stage, for the report
  std::optional<CloudScale> scale;
  std::uint64_t seed = 0;
};

struct RunContext {
  const PipelineOptions* options = nullptr;
  OutputTransaction* outputs = nullptr;  // every file the run writes, made visible when it succeeds
  std::string input_path, output_path;
  std::vector<std::string> warnings;
  ReportInput* report = nullptr;
};

const CloudScale& scale_of(Data& d) {
  if (!d.scale) {
    if (!d.cloud) throw InputError("this stage needs a point cloud, but the pipeline has none at this point");
    d.scale = measure_scale(*d.cloud);
  }
  return *d.scale;
}

PointCloud& need_cloud(Data& d, const char* stage) {
  if (!d.cloud) throw InputError(std::string(stage) + " needs a point cloud, but the pipeline has none at this point");
  return *d.cloud;
}

Mesh& need_mesh(Data& d, const char* stage) {
  if (!d.mesh) throw InputError(std::string(stage) + " needs a mesh, but the pipeline has none at this point (mesh the cloud first)");
  return *d.mesh;
}

// A stage: binds its options (from YAML or for the schema) and runs.
struct Stage {
  virtual ~Stage() = default;
  virtual void bind(Binder& b) = 0;
  virtual void run(Data& d, RunContext& ctx) = 0;
  std::string details;
  std::vector<std::pair<std::string, std::string>> decision_text;  // see StageRecord
  std::vector<std::pair<std::string, double>> decision_numbers;
};

struct ReaderStage : Stage {
  std::string filename;
  void bind(Binder& b) override { b.text("filename", filename); }
  void run(Data& d, RunContext& ctx) override {
    const std::string ext = lower_extension(filename);
    bool as_mesh = is_mesh_extension(ext) && ext != ".ply";
    if (ext == ".ply") {
      // A PLY with faces is a mesh, without faces a cloud.
      const std::string head = read_file_head(filename, 4096);
      as_mesh = head.find("element face") != std::string::npos && head.find("element face 0\n") == std::string::npos;
    }
    if (as_mesh) {
      d.mesh = read_mesh(filename, &ctx.warnings);
    } else {
      d.cloud = read_cloud(filename, &ctx.warnings);
      d.scale = measure_scale(*d.cloud);
      if (ctx.report) {
        ctx.report->input_points = d.cloud->finite_count();
        ctx.report->input_spacing = d.scale->spacing;
        ctx.report->input_diagonal = d.scale->diagonal;
      }
    }
  }
};

struct WriterStage : Stage {
  std::string filename;
  bool ascii = false;
  void bind(Binder& b) override {
    b.text("filename", filename);
    b.flag("ascii", ascii);
  }
  void run(Data& d, RunContext& ctx) override {
    const std::string ext = lower_extension(filename);
    if (d.mesh) {
      if (d.mesh->faces.empty()) throw InputError("nothing to write: the mesh has no faces");
      for (const auto& p : d.mesh->positions)
        if (!p.allFinite()) throw InputError("the mesh has non-finite coordinates; nothing is written");
      WriteOptions w;
      w.binary = !ascii;
      ctx.outputs->write(filename, encode_mesh(*d.mesh, ext, w));
    } else if (d.cloud) {
      if (d.cloud->finite_count() == 0) throw InputError("nothing to write: the cloud has no points");
      ctx.outputs->write(filename, encode_cloud(*d.cloud, ext == ".pcd" ? ".pcd" : ".ply"));
    } else {
      throw InputError("nothing to write: the pipeline produced neither a cloud nor a mesh");
    }
  }
};

struct CropStage : Stage {
  CropOptions o;
  void bind(Binder& b) override {
    b.vec3("min", o.min);
    b.vec3("max", o.max);
  }
  void run(Data& d, RunContext&) override { crop(need_cloud(d, "cloud.crop"), o); }
};

struct VoxelStage : Stage {
  VoxelOptions o{Length::spacings(1.0)};
  void bind(Binder& b) override { b.length("leaf", o.leaf); }
  void run(Data& d, RunContext&) override { voxel_downsample(need_cloud(d, "cloud.voxel"), o, scale_of(d)); }
};

struct OutlierStage : Stage {
  OutlierOptions o;
  void bind(Binder& b) override {
    b.integer("neighbours", o.neighbours, 1, 1000);
    b.number("std_ratio", o.std_ratio, 0.01, 100.0);
    b.length("radius", o.radius);
    b.integer("min_neighbours", o.min_neighbours, 0, 1000);
  }
  void run(Data& d, RunContext&) override { remove_outliers(need_cloud(d, "cloud.outliers"), o, scale_of(d)); }
};

struct NormalStage : Stage {
  NormalOptions o;
  bool keep = false;
  void bind(Binder& b) override {
    b.integer("neighbours", o.neighbours, 3, 1000);
    b.flag("orient", o.orient);
    b.flag("keep_normals", keep);
  }
  void run(Data& d, RunContext&) override {
    PointCloud& c = need_cloud(d, "cloud.normals");
    if (keep && c.has_normals()) return;
    estimate_normals(c, o);
  }
};

struct MlsStage : Stage {
  MlsOptions o;
  void bind(Binder& b) override {
    b.length("radius", o.radius);
    b.integer("polynomial_order", o.polynomial_order, 0, 3);
  }
  void run(Data& d, RunContext&) override { smooth_mls(need_cloud(d, "cloud.mls"), o, scale_of(d)); }
};

struct Gp3Stage : Stage {
  Gp3Options o;
  void bind(Binder& b) override {
    b.length("radius", o.radius);
    b.number("mu", o.mu, 1.0, 10.0);
    b.integer("max_neighbours", o.max_neighbours, 10, 10000);
    b.number("max_surface_angle", o.max_surface_angle_deg, 1.0, 180.0);
    b.number("min_angle", o.min_angle_deg, 0.0, 60.0);
    b.number("max_angle", o.max_angle_deg, 60.0, 180.0);
  }
  void run(Data& d, RunContext&) override { d.mesh = triangulate_gp3(need_cloud(d, "mesh.gp3"), o, scale_of(d)); }
};

struct OrganizedStage : Stage {
  OrganizedOptions o;
  void bind(Binder& b) override {
    b.length("max_edge", o.max_edge);
    b.number("max_view_angle", o.max_view_angle_deg, 1.0, 90.0);
  }
  void run(Data& d, RunContext&) override { d.mesh = triangulate_organized(need_cloud(d, "mesh.organized"), o, scale_of(d)); }
};

struct AutoMeshStage : Stage {
  Gp3Options gp3;
  OrganizedOptions organized;
  void bind(Binder& b) override {
    b.length("radius", gp3.radius);
    b.length("max_edge", organized.max_edge);
  }
  void run(Data& d, RunContext&) override {
    PointCloud& c = need_cloud(d, "mesh.auto");
    if (c.organized()) {
      d.mesh = triangulate_organized(c, organized, scale_of(d));
      details = "organized cloud: organized meshing";
    } else {
      if (!c.has_normals()) estimate_normals(c, NormalOptions{});
      d.mesh = triangulate_gp3(c, gp3, scale_of(d));
      details = "unorganized cloud: greedy projection";
    }
  }
};

struct PoissonStage : Stage {
  PoissonOptions o;
  void bind(Binder& b) override {
    b.integer("depth", o.depth, 4, 12);
    b.length("trim", o.trim_distance);
    b.flag("watertight", o.watertight);
  }
  void run(Data& d, RunContext&) override { d.mesh = triangulate_poisson(need_cloud(d, "mesh.poisson"), o, scale_of(d)); }
};

struct CleanupStage : Stage {
  CleanupOptions o;
  void bind(Binder& b) override {
    b.flag("remove_degenerate", o.remove_degenerate);
    b.flag("remove_duplicates", o.remove_duplicates);
    b.flag("fix_nonmanifold", o.fix_nonmanifold);
    b.integer("min_component", o.min_component_faces, 0, 1 << 30);
    b.flag("orient", o.orient);
  }
  void run(Data& d, RunContext&) override {
    const std::optional<Vec3> sensor = d.cloud ? d.cloud->sensor_origin : std::nullopt;
    const CleanupReport r = clean_mesh(need_mesh(d, "mesh.cleanup"), o, sensor);
    details = std::to_string(r.degenerate_faces + r.duplicate_faces + r.nonmanifold_faces + r.small_component_faces) + " faces removed, " +
              std::to_string(r.split_vertices) + " vertices split, " + std::to_string(r.flipped_faces) + " flipped";
  }
};

struct DenoiseStage : Stage {
  DenoiseOptions o;
  bool auto_params = false, free_boundary = false;
  bool set_sigma = false, set_lambda = false, set_iterations = false, set_radius = false;
  double sigma_s = 0, lambda = 0;
  int iterations = 0;
  void bind(Binder& b) override {
    sigma_s = o.sigma_s;
    lambda = o.lambda;
    iterations = o.iterations;
    b.number("sigma_s", sigma_s, 1e-3, 2.0);
    b.number("lambda", lambda, 0.0, 1.0);
    b.integer("iterations", iterations, 0, 100000);
    b.flag("auto", auto_params);
    b.number("decay", o.decay, 0.0, 1.0);
    b.number("radius_factor", o.radius_factor, 0.5, 10.0);
    b.choice("estimator", o.estimator, {{"tukey", RobustEstimator::tukey}, {"gaussian", RobustEstimator::gaussian},
                                         {"huber", RobustEstimator::huber}, {"lorentzian", RobustEstimator::lorentzian}});
    b.choice("neighbourhood", o.neighbourhood, {{"ball", NeighbourhoodKind::ball}, {"connected_ball", NeighbourhoodKind::connected_ball}});
    b.flag("recompute_neighbourhoods", o.recompute_neighbourhoods);
    b.flag("free_boundary", free_boundary);
    b.number("boundary_window", o.boundary_window, 0.5, 10.0);
    b.flag("feature_aware_fidelity", o.feature_aware_fidelity);
    // Explicit values win over --auto, as on the command line.
    set_sigma = b.present("sigma_s");
    set_lambda = b.present("lambda");
    set_iterations = b.present("iterations");
    set_radius = b.present("radius_factor");
  }
  void run(Data& d, RunContext& ctx) override {
    Mesh& m = need_mesh(d, "mesh.denoise");
    DenoiseOptions opt = o;
    opt.keep_boundary = !free_boundary;
    opt.sigma_s = sigma_s;
    opt.lambda = lambda;
    opt.iterations = iterations;
    if (!d.before) d.before = m;
    const auto* progress = &ctx.options->progress;
    const ProgressCallback report_progress = [progress](int done, int total) {
      if (*progress) (*progress)("mesh.denoise", done, total);
    };
    if (auto_params) {
      std::vector<std::string> given;
      if (set_sigma) given.push_back("sigma_s");
      if (set_lambda) given.push_back("lambda");
      if (set_iterations) given.push_back("iterations");
      if (set_radius) given.push_back("radius_factor");
      const AutoReport a = denoise_auto(m, opt, given, {}, report_progress);
      char buf[512];
      std::snprintf(buf, sizeof buf, "auto: noise %.3f x mean edge; %s: %s -> sigma_s %.3g, lambda %.3g, %d iterations (%s), radius factor %.3g; check %s",
                    a.noise_level, a.mode.c_str(), a.reason.c_str(), a.options.sigma_s, a.options.lambda, a.run.iterations,
                    a.run.stop_reason.c_str(), a.options.radius_factor, a.check.c_str());
      details = buf;
      decision_text = {{"mode", a.mode}, {"reason", a.reason}, {"stop_reason", a.run.stop_reason}, {"check", a.check}};
      decision_numbers = {{"noise_level", a.noise_level},
                          {"noise", a.noise},
                          {"exact_plane_fraction", a.exact_plane_fraction},
                          {"isolated_outlier_share", a.impulsive_share},
                          {"soft_crease_share", a.crease_share},
                          {"sigma_s", a.options.sigma_s},
                          {"lambda", a.options.lambda},
                          {"radius_factor", a.options.radius_factor},
                          {"iterations", static_cast<double>(a.run.iterations)},
                          {"probe_iterations", static_cast<double>(a.probe_iterations)},
                          {"displacement", a.run.displacement}};
      if (a.check != "passed" && a.check != "not needed")
        ctx.warnings.push_back("mesh.denoise: the result check ended the run early (" + a.check + ")");
      return;
    }
    char buf[128];
    std::snprintf(buf, sizeof buf, "sigma_s %.3g, lambda %.3g, iterations %d, radius factor %.3g", opt.sigma_s, opt.lambda,
                  opt.iterations, opt.radius_factor);
    details = buf;
    denoise(m, opt, report_progress);
  }
};

struct NoiseStage : Stage {
  NoiseOptions o;
  void bind(Binder& b) override {
    b.number("level", o.level, 0.0, 100.0);
    b.choice("kind", o.kind, {{"gaussian", NoiseKind::gaussian}, {"uniform", NoiseKind::uniform}, {"impulsive", NoiseKind::impulsive}});
    b.choice("direction", o.direction, {{"random", NoiseDirection::random}, {"normal", NoiseDirection::normal}});
    b.number("fraction", o.impulsive_fraction, 1e-9, 1.0);
    b.seed("seed", o.seed);
  }
  void run(Data& d, RunContext&) override {
    add_noise(need_mesh(d, "mesh.noise"), o);
    d.seed = o.seed;
  }
};

struct ScanStage : Stage {
  VirtualScanOptions o;
  void bind(Binder& b) override {
    b.integer("views", o.views, 1, 1000);
    b.integer("width", o.width, 2, 10000);
    b.integer("height", o.height, 2, 10000);
    b.number("fov", o.fov_deg, 1.0, 170.0);
    b.number("noise", o.noise, 0.0, 100.0);
    b.seed("seed", o.seed);
  }
  void run(Data& d, RunContext&) override {
    d.cloud = merge_scans(virtual_scan(need_mesh(d, "scan.virtual"), o));
    d.mesh.reset();
    d.before.reset();
    d.scale = measure_scale(*d.cloud);
    d.seed = o.seed;
  }
};

struct ReportStage : Stage {
  ReportOptions o;
  void bind(Binder& b) override {
    b.text("reference", o.reference);
    b.flag("figures", o.figures);
    b.integer("image_size", o.image_size, 200, 4000);
  }
  void run(Data&, RunContext&) override {}  // written at the end of the run, when all timings are known
};

using Factory = std::unique_ptr<Stage> (*)();
template <typename T>
std::unique_ptr<Stage> make() {
  return std::make_unique<T>();
}

const std::vector<std::pair<std::string, Factory>>& registry() {
  static const std::vector<std::pair<std::string, Factory>> r = {
      {"read", make<ReaderStage>},           {"write", make<WriterStage>},         {"cloud.crop", make<CropStage>},
      {"cloud.voxel", make<VoxelStage>},     {"cloud.outliers", make<OutlierStage>}, {"cloud.normals", make<NormalStage>},
      {"cloud.mls", make<MlsStage>},         {"mesh.auto", make<AutoMeshStage>},   {"mesh.gp3", make<Gp3Stage>},
      {"mesh.organized", make<OrganizedStage>}, {"mesh.poisson", make<PoissonStage>}, {"mesh.cleanup", make<CleanupStage>},
      {"mesh.denoise", make<DenoiseStage>},  {"mesh.noise", make<NoiseStage>},     {"scan.virtual", make<ScanStage>},
      {"report", make<ReportStage>},
  };
  return r;
}

std::vector<std::string> type_names() {
  std::vector<std::string> n;
  for (const auto& [name, f] : registry()) n.push_back(name);
  return n;
}

struct StageSlot {
  Where where;
  std::vector<std::string> inputs;
  YAML::Node options;  // the stage's map (or a map holding filename for bare strings)
  std::unique_ptr<Stage> stage;
};

}  // namespace

struct Pipeline::Impl {
  std::string path;
  PipelineOptions options;
  std::vector<StageSlot> slots;
  std::string output;
  YAML::Node resolved;
};

Pipeline::Pipeline(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Pipeline::~Pipeline() = default;
Pipeline::Pipeline(Pipeline&&) noexcept = default;
Pipeline& Pipeline::operator=(Pipeline&&) noexcept = default;
const std::string& Pipeline::output() const { return impl_->output; }
bool Pipeline::has_report() const {
  for (const auto& s : impl_->slots)
    if (s.where.type == "report") return true;
  return false;
}
std::string Pipeline::resolved_config() const { return YAML::Dump(impl_->resolved) + "\n"; }

std::vector<std::pair<std::string, std::vector<std::string>>> pipeline_schema() {
  std::vector<std::pair<std::string, std::vector<std::string>>> out;
  for (const auto& [name, factory] : registry()) {
    Binder b;
    factory()->bind(b);
    out.emplace_back(name, b.names());
  }
  return out;
}

Pipeline Pipeline::load(const std::string& path, const PipelineOptions& options) {
  std::string text;
  try {
    text = read_file(path);
  } catch (const InputError& e) {
    throw ConfigError(std::string("pipeline: ") + e.what());
  }
  return parse(text, path, options);
}

Pipeline Pipeline::parse(std::string_view yaml, const std::string& path, const PipelineOptions& options) {
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  impl->options = options;
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml));
  } catch (const YAML::ParserException& e) {
    throw ConfigError(path + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw ConfigError(path + ": YAML error: " + e.msg);
  }
  YAML::Node list = root;
  if (root.IsMap()) {
    if (!root["pipeline"]) throw ConfigError(path + ":" + std::to_string(root.Mark().line + 1) + ": expected a 'pipeline:' list of stages");
    for (auto it = root.begin(); it != root.end(); ++it)
      if (it->first.Scalar() != "pipeline")
        throw ConfigError(path + ":" + std::to_string(it->first.Mark().line + 1) + ": unknown top-level key '" + it->first.Scalar() +
                          "'; the file holds 'pipeline:' only");
    list = root["pipeline"];
  }
  if (!list.IsSequence() || list.size() == 0)
    throw ConfigError(path + ":" + std::to_string(list.Mark().line + 1) + ": the pipeline must be a non-empty list of stages");

  std::map<std::string, int> tags;
  const std::size_t n = list.size();
  for (std::size_t i = 0; i < n; ++i) {
    const YAML::Node item = list[i];
    StageSlot slot;
    slot.where.file = path;
    slot.where.line = item.Mark().line + 1;
    slot.where.index = static_cast<int>(i);
    if (item.IsScalar()) {
      if (i != 0 && i + 1 != n)
        throw ConfigError(path + ":" + std::to_string(slot.where.line) + ": stage " + std::to_string(i + 1) + ": a bare file name ('" +
                          item.Scalar() + "') must be the first stage (reader) or the last (writer)");
      slot.where.type = i == 0 ? "read" : "write";
      slot.options = YAML::Node(YAML::NodeType::Map);
      slot.options["filename"] = item.Scalar();
    } else if (item.IsMap()) {
      const YAML::Node type = item["type"];
      if (!type || !type.IsScalar())
        throw ConfigError(path + ":" + std::to_string(slot.where.line) + ": stage " + std::to_string(i + 1) +
                          " has no 'type'; valid types: " + detail::join(type_names()));
      slot.where.type = type.Scalar();
      bool known = false;
      for (const auto& t : type_names()) known = known || t == slot.where.type;
      if (!known)
        throw ConfigError(path + ":" + std::to_string(type.Mark().line + 1) + ": stage " + std::to_string(i + 1) + ": unknown stage type '" +
                          slot.where.type + "'; " + detail::did_you_mean(slot.where.type, type_names()) + "valid: " + detail::join(type_names()));
      if (item["tag"]) {
        if (!item["tag"].IsScalar()) throw ConfigError(slot.where.prefix(item["tag"].Mark().line + 1) + ": 'tag' must be a name");
        slot.where.tag = item["tag"].Scalar();
        if (tags.count(slot.where.tag))
          throw ConfigError(slot.where.prefix(item["tag"].Mark().line + 1) + ": tag '" + slot.where.tag + "' is used twice");
      }
      if (const YAML::Node in = item["inputs"]) {
        std::vector<std::string> names;
        if (in.IsScalar()) names.push_back(in.Scalar());
        else if (in.IsSequence())
          for (const auto& x : in) names.push_back(x.Scalar());
        for (const auto& t : names) {
          if (!tags.count(t)) {
            std::vector<std::string> known_tags;
            for (const auto& [k, v] : tags) known_tags.push_back(k);
            throw ConfigError(slot.where.prefix(in.Mark().line + 1) + ": key 'inputs': no earlier stage has the tag '" + t + "'; " +
                              detail::did_you_mean(t, known_tags) + "tags so far: " + (known_tags.empty() ? "(none)" : detail::join(known_tags)));
          }
          slot.inputs.push_back(t);
        }
        if (slot.inputs.size() > 1)
          throw ConfigError(slot.where.prefix(in.Mark().line + 1) + ": key 'inputs': stages take one input; got " + std::to_string(slot.inputs.size()));
      }
      slot.options = item;  // the loaded node itself: its marks give line numbers
    } else {
      throw ConfigError(path + ":" + std::to_string(slot.where.line) + ": stage " + std::to_string(i + 1) +
                        " must be a file name or a map with 'type'");
    }
    if (!slot.where.tag.empty()) tags[slot.where.tag] = static_cast<int>(i);
    impl->slots.push_back(std::move(slot));
  }

  // Command-line replacements and overrides.
  if (options.input) {
    if (impl->slots.front().where.type != "read")
      throw ConfigError(path + ": --input needs the pipeline to start with a reader (a file name)");
    impl->slots.front().options["filename"] = *options.input;
  }
  if (options.output) {
    if (impl->slots.back().where.type != "write" && !(impl->slots.size() > 1 && impl->slots.back().where.type == "report"))
      throw ConfigError(path + ": --output needs the pipeline to end with a writer (a file name)");
  }
  for (const auto& set : options.sets) {
    const auto eq = set.find('='), dot = set.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq)
      throw ConfigError("--set '" + set + "': expected TAG.OPTION=VALUE");
    // The tag may itself contain a dot when a stage type is used as tag (mesh.denoise.sigma_s=...).
    const std::string lhs = set.substr(0, eq), value = set.substr(eq + 1);
    const auto last_dot = lhs.rfind('.');
    const std::string tag = lhs.substr(0, last_dot), option = lhs.substr(last_dot + 1);
    StageSlot* target = nullptr;
    std::vector<std::string> names;
    for (auto& s : impl->slots) {
      if (!s.where.tag.empty()) names.push_back(s.where.tag);
      if (s.where.tag == tag) target = &s;
    }
    if (!target) {
      int matches = 0;
      for (auto& s : impl->slots)
        if (s.where.type == tag) {
          target = &s;
          ++matches;
        }
      if (matches > 1) throw ConfigError("--set '" + set + "': several stages have type '" + tag + "'; give one a tag");
    }
    if (!target)
      throw ConfigError("--set '" + set + "': no stage has the tag '" + tag + "'; " + detail::did_you_mean(tag, names) +
                        "tags: " + (names.empty() ? std::string("(none)") : detail::join(names)));
    try {
      target->options[option] = YAML::Load(value);
    } catch (const YAML::Exception&) {
      target->options[option] = value;
    }
  }
  // The writer: the last "write" stage (a report may follow it).
  for (auto& s : impl->slots)
    if (s.where.type == "write" && options.output) s.options["filename"] = *options.output;

  // Bind every stage's options now, so every mistake surfaces before anything runs.
  YAML::Node resolved(YAML::NodeType::Sequence);
  for (auto& s : impl->slots) {
    for (const auto& [name, factory] : registry())
      if (name == s.where.type) s.stage = factory();
    Binder b(s.options, s.where);
    s.stage->bind(b);
    b.finish();
    resolved.push_back(s.options);
  }
  impl->resolved = YAML::Node(YAML::NodeType::Map);
  impl->resolved["pipeline"] = resolved;

  // Files: readers must exist, writers must be writable formats and never the input.
  for (auto& s : impl->slots) {
    if (s.where.type == "read") {
      const std::string f = static_cast<ReaderStage*>(s.stage.get())->filename;
      const std::string ext = lower_extension(f);
      if (!is_mesh_extension(ext) && !is_cloud_extension(ext))
        throw ConfigError(s.where.prefix() + ": key 'filename': unknown format '" + ext + "'; readers: .ply .obj .off .stl .pcd .xyz .txt .pts");
      if (!std::filesystem::exists(f)) throw ConfigError(s.where.prefix() + ": key 'filename': input file '" + f + "' does not exist");
    }
    if (s.where.type == "write") {
      const std::string f = static_cast<WriterStage*>(s.stage.get())->filename;
      const std::string ext = lower_extension(f);
      if (!is_mesh_extension(ext) && ext != ".pcd")
        throw ConfigError(s.where.prefix() + ": key 'filename': unknown output format '" + ext + "'; writers: .ply .obj .off .stl (mesh), .ply .pcd (cloud)");
      impl->output = f;
    }
    if (s.where.type == "report") {
      const std::string ref = static_cast<ReportStage*>(s.stage.get())->o.reference;
      if (!ref.empty() && !std::filesystem::exists(ref))
        throw ConfigError(s.where.prefix() + ": key 'reference': file '" + ref + "' does not exist");
    }
  }
  // No stage may write over any file the pipeline reads, and every output folder must exist and be
  // writable, so a run cannot compute everything and then fail at the end.
  std::vector<std::string> inputs;
  for (auto& s : impl->slots) {
    if (s.where.type == "read") inputs.push_back(static_cast<ReaderStage*>(s.stage.get())->filename);
    if (s.where.type == "report" && !static_cast<ReportStage*>(s.stage.get())->o.reference.empty())
      inputs.push_back(static_cast<ReportStage*>(s.stage.get())->o.reference);
  }
  for (auto& s : impl->slots) {
    if (s.where.type != "write") continue;
    const std::string f = static_cast<WriterStage*>(s.stage.get())->filename;
    for (const auto& in : inputs)
      if (f == in || same_file(f, in))
        throw ConfigError(s.where.prefix() + ": key 'filename': '" + f + "' is an input of this pipeline; scanmesh never overwrites its input");
    try {
      check_writable(f);
    } catch (const OutputError& e) {
      throw ConfigError(s.where.prefix() + ": key 'filename': " + e.what());
    }
  }
  return Pipeline(std::move(impl));
}

PipelineResult Pipeline::run() {
  const auto t0 = std::chrono::steady_clock::now();
  set_thread_count(impl_->options.threads);
  ReportInput report;
  report.output_path = impl_->output;
  report.tool_version = SCANMESH_VERSION;
  report.config_yaml = resolved_config();
  report.threads = thread_count();
  OutputTransaction outputs;
  RunContext ctx;
  ctx.options = &impl_->options;
  ctx.outputs = &outputs;
  ctx.report = &report;
  const ReportStage* report_stage = nullptr;
  for (const auto& s : impl_->slots) {
    if (s.where.type == "report") report_stage = static_cast<const ReportStage*>(s.stage.get());
    if (s.where.type == "read") report.input_path = static_cast<const ReaderStage*>(s.stage.get())->filename;
  }
  Data data;
  std::map<std::string, Data> tagged;
  std::optional<Mesh> reference;
  PipelineResult result;
  result.output = impl_->output;
  try {
    if (report_stage && !report_stage->o.reference.empty()) reference = read_mesh(report_stage->o.reference, &ctx.warnings);
    for (auto& s : impl_->slots) {
      if (!s.inputs.empty()) data = tagged.at(s.inputs.front());
      const auto ts = std::chrono::steady_clock::now();
      try {
        s.stage->run(data, ctx);
      } catch (const Error& e) {
        throw InputError(s.where.prefix() + ": " + e.what());
      }
      StageRecord rec;
      rec.type = s.where.type;
      rec.tag = s.where.tag;
      rec.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count();
      rusage u{};
      getrusage(RUSAGE_SELF, &u);
      rec.peak_memory_mb = static_cast<double>(u.ru_maxrss) / 1024.0;
      rec.points = data.cloud ? data.cloud->finite_count() : 0;
      rec.vertices = data.mesh ? data.mesh->num_vertices() : 0;
      rec.faces = data.mesh ? data.mesh->num_faces() : 0;
      rec.details = s.stage->details;
      rec.decision_text = s.stage->decision_text;
      rec.decision_numbers = s.stage->decision_numbers;
      report.stages.push_back(rec);
      if (impl_->options.log) {
        char line[256];
        std::snprintf(line, sizeof line, "%-15s %7.3f s  %zu points, %zu faces%s%s", rec.type.c_str(), rec.seconds, rec.points, rec.faces,
                      rec.details.empty() ? "" : "  ", rec.details.c_str());
        impl_->options.log(line);
      }
      if (!s.where.tag.empty()) tagged[s.where.tag] = data;
    }
    report.seed = data.seed;
    report.warnings = ctx.warnings;
    if (report_stage) {
      report.mesh = data.mesh ? &*data.mesh : nullptr;
      report.before = data.before ? &*data.before : nullptr;
      report.reference = reference ? &*reference : nullptr;
      result.report_files = write_report(report, report_stage->o, outputs);
      const ReportPaths p = report_paths(impl_->output);
      result.report_files.insert(result.report_files.begin(), p.json);
      if (report_stage->o.figures) result.report_files.push_back(p.html);
    }
    outputs.commit();
  } catch (const std::exception& e) {
    if (report_stage && !impl_->output.empty()) {
      report.status = "failed";
      report.warnings = ctx.warnings;
      try {
        write_failure_sidecar(report, e.what());
      } catch (...) {
      }
    }
    throw;
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace scanmesh
