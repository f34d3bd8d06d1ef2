// report: the JSON sidecar, figures and HTML page of the run, written after the last stage.
#include "scanmesh/mesh_io.h"
#include "scanmesh/report.h"
#include "stage.h"

namespace scanmesh::detail {
namespace {

struct ReportStage : Stage {
  ReportOptions o;
  std::optional<Mesh> reference;
  void bind(Binder& b) override { bind_options(b, o); }
  [[nodiscard]] std::vector<std::string> files_read() const override {
    return o.reference.empty() ? std::vector<std::string>{} : std::vector<std::string>{o.reference};
  }
  [[nodiscard]] bool is_report() const override { return true; }
  void prepare(RunContext& ctx) override {
    if (!o.reference.empty()) reference = read_mesh(o.reference, &ctx.warnings);
  }
  void run(Data&, RunContext&) override {}  // written at the end of the run, when all timings are known
  std::vector<std::string> write_report(ReportInput& report, const Data& data, RunContext& ctx) override {
    report.mesh = data.mesh ? &*data.mesh : nullptr;
    report.before = data.before ? &*data.before : nullptr;
    report.reference = reference ? &*reference : nullptr;
    std::vector<std::string> files = scanmesh::write_report(report, o, *ctx.outputs);
    const ReportPaths p = report_paths(report.output_path);
    files.insert(files.begin(), p.json);
    if (o.figures) files.push_back(p.html);
    return files;
  }
  void write_failure(ReportInput& report, const std::string& error) override {
    report.status = "failed";
    write_failure_sidecar(report, error);
  }
};

}  // namespace

void register_report_stages(StageRegistry& r) {
  r.add("report", [] { return std::make_unique<ReportStage>(); });
}

}  // namespace scanmesh::detail
