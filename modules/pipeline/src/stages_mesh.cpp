// mesh.auto, mesh.gp3, mesh.organized, mesh.poisson and mesh.cleanup: cloud -> mesh with PCL, then repair.
#include "scanmesh/clean_mesh.h"
#include "scanmesh/mesh_cloud.h"
#include "stage.h"

namespace scanmesh::detail {
namespace {

// mesh.auto takes the method and every method's options; the named methods are mesh.auto with the
// method fixed and only their own options.
struct MeshStage : Stage {
  [[nodiscard]] bool reports_progress() const override { return true; }
  MeshMethodOptions method;
  Gp3Options gp3;
  OrganizedOptions organized;
  PoissonOptions poisson;
  bool fixed;
  explicit MeshStage(std::optional<MeshMethod> only) : fixed(only.has_value()) {
    if (only) method.method = *only;
  }
  void bind(Binder& b) override {
    if (!fixed) bind_options(b, method);
    if (!fixed || method.method == MeshMethod::gp3) bind_options(b, gp3);
    if (!fixed || method.method == MeshMethod::organized) bind_options(b, organized);
    if (!fixed || method.method == MeshMethod::poisson) bind_options(b, poisson);
  }
  void run(Data& d, RunContext& ctx) override {
    MeshingDecision decision;
    PointCloud& cloud = need_cloud(d, "meshing");
    std::function<void(const std::string&)> note;
    if (ctx.options != nullptr && ctx.options->log) note = [&ctx](const std::string& line) { ctx.options->log("mesh.auto: " + line); };
    d.mesh = mesh_cloud(cloud, method, gp3, organized, poisson, scale_of(d), &decision, note);
    Data::Meshed meshed;
    for (const Vec3& p : cloud.points)
      if (p.allFinite()) meshed.points.push_back(p);
    meshed.spacing = scale_of(d).spacing;
    meshed.from_grid = decision.method == MeshMethod::organized;
    if (decision.fit.point_distance.size() == meshed.points.size()) {
      decision.fit.layered_faces.clear();
      meshed.fit = std::make_shared<const ScanFit>(std::move(decision.fit));
    }
    d.meshed = std::move(meshed);
    d.scanned_mesh = true;
    d.mesh_keeps_points = decision.method != MeshMethod::poisson;
    details = decision.reason;
    decision_text = {{"method", method_name(decision.method)}, {"reason", decision.reason}};
    decision_numbers = decision.numbers;
    if (d.mesh->faces.empty()) throw InputError("meshing produced no triangles (too few points, or try a larger gp3_radius)");
  }
};

struct CleanupStage : Stage {
  CleanupOptions o;
  void bind(Binder& b) override { bind_options(b, o); }
  void run(Data& d, RunContext& ctx) override {
    const std::optional<Vec3> sensor = d.cloud ? d.cloud->sensor_origin : std::nullopt;
    Mesh& m = need_mesh(d, "mesh.cleanup");
    const CleanupReport r = clean_mesh(m, o, sensor);
    details = std::to_string(r.degenerate_faces + r.duplicate_faces + r.nonmanifold_faces + r.small_component_faces + r.fold_faces) +
              " faces removed (" + std::to_string(r.fold_faces) + " folded over their neighbours), " + std::to_string(r.split_vertices) +
              " vertices split, " + std::to_string(r.flipped_faces) + " flipped";
    if (r.unorientable_edges > 0)
      ctx.warnings.push_back("mesh.cleanup: could not orient " + std::to_string(r.unorientable_edges) +
                             " edges consistently (their faces fold over each other)");
    if (m.faces.empty()) throw InputError("no triangles left after clean-up (" + details + ")");
  }
};

}  // namespace

void register_mesh_stages(StageRegistry& r) {
  r.add("mesh.auto", [] { return std::make_unique<MeshStage>(std::nullopt); });
  r.add("mesh.gp3", [] { return std::make_unique<MeshStage>(MeshMethod::gp3); });
  r.add("mesh.organized", [] { return std::make_unique<MeshStage>(MeshMethod::organized); });
  r.add("mesh.poisson", [] { return std::make_unique<MeshStage>(MeshMethod::poisson); });
  r.add("mesh.cleanup", [] { return std::make_unique<CleanupStage>(); });
}

}  // namespace scanmesh::detail
