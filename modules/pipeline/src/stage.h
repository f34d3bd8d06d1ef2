#pragma once
// What a pipeline stage is, inside the pipeline module: the data flowing between stages, the run's
// context, the Stage interface and the registry of stage types. Stage families register themselves
// (stages_*.cpp); the loader and the run loop only see this interface.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "binder.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/length.h"
#include "scanmesh/mesh.h"
#include "scanmesh/pipeline.h"
#include "scanmesh/point_cloud.h"

namespace scanmesh {
struct ReportInput;
}

namespace scanmesh::detail {

/// What flows from stage to stage.
struct Data {
  std::optional<PointCloud> cloud;
  std::optional<Mesh> mesh;
  std::optional<Mesh> before;  ///< the mesh before the first vertex-moving stage, for the report
  std::optional<CloudScale> scale;
  std::uint64_t seed = 0;
  /// The points the mesh was made from (set by the meshing stages), for the scan-fit check at the end.
  struct Meshed {
    std::vector<Vec3> points;
    double spacing = 0.0;
    bool from_grid = false;
    /// How the mesh as meshing left it fits `points` (when meshing measured it: mesh.auto on an
    /// unorganized cloud): the final report judges the loops by it (measure_scan_fit's `as_meshed`).
    std::shared_ptr<const ScanFit> fit;
  };
  std::optional<Meshed> meshed;
  /// The mesh was triangulated from scanned points here and nothing has added noise to it since: every
  /// vertex carries the scanner's noise, and the cloud's outliers were removed before meshing
  /// (DenoiseOptions::scanned).
  bool scanned_mesh = false;
  /// ...and its vertices are the scanned points (greedy projection, organized meshing; not Poisson):
  /// DenoiseOptions::vertices_are_points.
  bool mesh_keeps_points = false;
};

/// What every stage of one run shares.
struct RunContext {
  const PipelineOptions* options = nullptr;
  OutputTransaction* outputs = nullptr;  ///< every file the run writes, made visible when it succeeds
  std::vector<std::string> warnings;
  std::vector<std::string> problems;  ///< why the result is degraded (status "degraded"); also warnings
  ReportInput* report = nullptr;
  bool report_wanted = false;  ///< the pipeline has a report stage
};

/// The point spacing and extent of the cloud, measured once.
const CloudScale& scale_of(Data& d);
PointCloud& need_cloud(Data& d, const char* stage);
Mesh& need_mesh(Data& d, const char* stage);

/// One stage: binds its options (from YAML, or in schema mode only lists them) and runs.
struct Stage {
  virtual ~Stage() = default;
  virtual void bind(Binder& b) = 0;
  /// Before any stage runs (e.g. read a reference), so input errors surface before the work.
  virtual void prepare(RunContext&) {}
  virtual void run(Data& d, RunContext& ctx) = 0;
  /// Stages that combine several earlier results (cloud.merge, cloud.register) take them all here, in the
  /// order `inputs` lists them, and write the combination to `out`.
  [[nodiscard]] virtual bool takes_many_inputs() const { return false; }
  /// True for stages that report their own progress while they run (the pipeline's heartbeat then stays
  /// quiet for them).
  [[nodiscard]] virtual bool reports_progress() const { return false; }
  virtual void run_many(const std::vector<const Data*>& /*inputs*/, Data& /*out*/, RunContext& /*ctx*/) {}
  /// Files this stage reads or writes (checked at loading: inputs exist, outputs writable, never an input).
  [[nodiscard]] virtual std::vector<std::string> files_read() const { return {}; }
  [[nodiscard]] virtual std::vector<std::string> files_written() const { return {}; }
  /// A report stage writes, after the last stage, the sidecar and figures into the run's outputs (and
  /// returns their names), or on failure a sidecar saying so.
  [[nodiscard]] virtual bool is_report() const { return false; }
  virtual std::vector<std::string> write_report(ReportInput&, const Data&, RunContext&) { return {}; }
  virtual void write_failure(ReportInput&, const std::string& /*error*/) {}

  std::string details;  ///< one line for the log and the sidecar
  std::vector<std::pair<std::string, std::string>> decision_text;  ///< see StageRecord
  std::vector<std::pair<std::string, double>> decision_numbers;
};

using StageFactory = std::function<std::unique_ptr<Stage>()>;

/// Stage types by name, in registration order.
class StageRegistry {
 public:
  void add(const std::string& type, StageFactory make);  ///< a type registered again is ignored
  /// nullptr if unknown.
  [[nodiscard]] const StageFactory* find(const std::string& type) const;
  [[nodiscard]] std::vector<std::string> types() const;

 private:
  std::vector<std::pair<std::string, StageFactory>> types_;
};

/// Every stage type this program knows: read, write, mesh.denoise and mesh.noise always; the PCL, VTK
/// and OpenCV families once register_scan_stages() (pipeline.h) has run.
StageRegistry& stage_registry();

/// The families (one stages_*.cpp each). The first two are in this library; the others in
/// scanmesh_pipeline_scans.
void register_io_stages(StageRegistry& r);
void register_denoise_stages(StageRegistry& r);
void register_cloud_stages(StageRegistry& r);
void register_mesh_stages(StageRegistry& r);
void register_virtual_scan_stages(StageRegistry& r);
void register_report_stages(StageRegistry& r);

/// Binds `options` of type O through its schema; `given` receives the names set explicitly.
template <class O>
void bind_options(Binder& b, O& options, std::vector<std::string>* given = nullptr) {
  BoundOptions<O> set(options, O::schema());
  b.options(set);
  if (given)
    for (std::size_t i = 0; i < set.size(); ++i)
      if (set.given(set.info(i).name)) given->push_back(set.info(i).name);
}

}  // namespace scanmesh::detail
