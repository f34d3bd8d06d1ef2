#pragma once
// YAML pipelines modelled on PDAL's: a `pipeline:` list (or a bare list) of stages. A bare string is a
// file: a reader if first, a writer if last (chosen by extension). A stage is a map with `type` (a dotted
// family: cloud.crop, cloud.voxel, cloud.outliers, cloud.normals, cloud.mls, mesh.auto, mesh.gp3,
// mesh.organized, mesh.poisson, mesh.cleanup, mesh.denoise, mesh.noise, scan.virtual, report), an optional
// unique `tag` and optional `inputs` (tags of earlier stages); every other key is an option, read into the
// same options struct the C++ API and the command line use. Every configuration error names FILE:LINE, the
// stage, the key and the valid choices, and is raised before anything runs.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scanmesh/errors.h"
#include "scanmesh/heartbeat.h"
#include "scanmesh/schema.h"

namespace scanmesh {

struct ScanFit;

/// A configuration error: bad YAML, unknown stage type or key, wrong value type, missing file, unknown tag.
class ConfigError : public UsageError {
 public:
  using UsageError::UsageError;
};

struct PipelineOptions {
  std::optional<std::string> input;   ///< replaces the first reader's file
  std::optional<std::string> output;  ///< replaces the last writer's file
  std::vector<std::string> sets;      ///< "TAG.OPTION=VALUE" overrides (the stage's type works as a tag too)
  int threads = 0;
  /// Called with (stage label, done, total) during long stages.
  std::function<void(const std::string&, int, int)> progress;
  /// Called with one line per finished stage.
  std::function<void(const std::string&)> log;
  /// A stage without progress lines of its own (reading, cloud clean-up, normals, mesh clean-up, ...)
  /// says "TYPE: still running (N s)" through `log` this often while it runs; 0 = never.
  double heartbeat_seconds = kHeartbeatSeconds;
};

/// One stage given in code (what the command-line verbs build): its type, tag and options as text, each
/// parsed by the stage's schema exactly as the same key in YAML.
struct StageSpec {
  std::string type;
  std::string tag;
  std::vector<std::pair<std::string, std::string>> options;
};

struct PipelineResult {
  std::string output;
  std::vector<std::string> report_files;  ///< sidecar, figures and page, if the pipeline has a report stage
  std::vector<std::string> warnings;      ///< what the stages warned about (also in the sidecar)
  /// "ok", or "degraded" when the result is written but falls short (the mesh leaves points of its scan
  /// out, has holes where the scan has data, or faces of opposite orientation); `problems` says how.
  std::string status = "ok";
  std::vector<std::string> problems;
  /// The final mesh against the points it was made from (pipelines that mesh a cloud), else null.
  std::shared_ptr<const ScanFit> scan_fit;
  std::string summary;                    ///< what came out: "V vertices, F faces, B boundary loops, C components"
  double seconds = 0.0;
};

/// A parsed and validated pipeline. Loading checks everything (syntax, types, keys, values, files, tags);
/// running then only fails on problems in the data.
class Pipeline {
 public:
  static Pipeline load(const std::string& path, const PipelineOptions& options);
  /// The same on YAML text in memory; `path` names it in messages.
  static Pipeline parse(std::string_view yaml, const std::string& path, const PipelineOptions& options);
  /// A pipeline from stages given in code; errors name options as command-line flags (--sigma-s).
  static Pipeline build(const std::vector<StageSpec>& stages, const PipelineOptions& options);
  ~Pipeline();
  Pipeline(Pipeline&&) noexcept;
  Pipeline& operator=(Pipeline&&) noexcept;

  [[nodiscard]] const std::string& output() const;
  [[nodiscard]] bool has_report() const;
  /// The configuration after --input/--output/--set, as YAML text.
  [[nodiscard]] std::string resolved_config() const;
  /// Runs every stage in order. On an error the report stage (if any) still writes a sidecar with
  /// status "failed", and the error is rethrown.
  PipelineResult run();

  struct Impl;  ///< opaque (pipeline_impl.h)

 private:
  explicit Pipeline(std::unique_ptr<Impl> impl);
  static Pipeline finish(std::unique_ptr<Impl> impl);  // overrides, binding and checks
  std::unique_ptr<Impl> impl_;
};

/// One option of a stage type, as its options struct's schema describes it.
struct StageOption {
  FieldInfo info;             ///< name (YAML key; the flag is --name-with-dashes), unit, range, doc
  std::string default_value;  ///< the default's text
};

/// The stage types this program knows, in registration order.
std::vector<std::string> stage_types();

/// The options of a stage type (what its YAML map, its command-line flags, --help and the README's
/// tables offer). Throws ConfigError for an unknown type.
std::vector<StageOption> stage_options(const std::string& type);

/// Stage types and, per type, its option names (for help texts and "did you mean").
std::vector<std::pair<std::string, std::vector<std::string>>> pipeline_schema();

/// Adds the stage families that need PCL, VTK or OpenCV (cloud.*, mesh.auto, mesh.gp3, mesh.organized,
/// mesh.poisson, mesh.cleanup, scan.virtual, report) to the registry; without them a pipeline knows read,
/// write, mesh.denoise and mesh.noise. Defined in the scanmesh_pipeline_scans library; idempotent.
void register_scan_stages();

}  // namespace scanmesh
