// cloud.*: point-cloud clean-up stages over clean_cloud.h.
#include <cstdio>

#include "scanmesh/clean_cloud.h"
#include "scanmesh/combine_views.h"
#include "scanmesh/dequantize.h"
#include "stage.h"

namespace scanmesh::detail {
namespace {

struct CropStage : Stage {
  CropOptions o;
  void bind(Binder& b) override { bind_options(b, o); }
  void run(Data& d, RunContext&) override { crop(need_cloud(d, "cloud.crop"), o); }
};

struct VoxelStage : Stage {
  VoxelOptions o;
  void bind(Binder& b) override { bind_options(b, o); }
  void run(Data& d, RunContext&) override {
    PointCloud& cloud = need_cloud(d, "cloud.voxel");
    const VoxelReport r = voxel_downsample(cloud, o, scale_of(d));
    char buf[192];
    if (r.leaf > 0.0) {
      std::snprintf(buf, sizeof buf, "%zu -> %zu points, voxel edge %.4g (%.2f x the point spacing)", r.before, r.after, r.leaf,
                    d.scale->spacing > 0.0 ? r.leaf / d.scale->spacing : 0.0);
      d.scale.reset();  // lengths in spacings after this stage mean the new spacing
    } else if (r.limit_skipped_organized) {
      std::snprintf(buf, sizeof buf, "%zu points, more than voxel_max_points %d, but organized: left whole", r.before, o.max_points);
    } else {
      std::snprintf(buf, sizeof buf, "%zu points: nothing to do", r.before);
    }
    details = buf;
    decision_numbers = {{"points_before", static_cast<double>(r.before)}, {"points_after", static_cast<double>(r.after)}};
    if (r.leaf > 0.0) decision_numbers.emplace_back("voxel_edge", r.leaf);
  }
};

struct OutlierStage : Stage {
  OutlierOptions o;
  void bind(Binder& b) override { bind_options(b, o); }
  void run(Data& d, RunContext&) override { remove_outliers(need_cloud(d, "cloud.outliers"), o, scale_of(d)); }
};

struct NormalStage : Stage {
  NormalOptions o;
  void bind(Binder& b) override { bind_options(b, o); }
  void run(Data& d, RunContext&) override { estimate_normals(need_cloud(d, "cloud.normals"), o); }
};

struct MlsStage : Stage {
  MlsOptions o;
  void bind(Binder& b) override { bind_options(b, o); }
  void run(Data& d, RunContext&) override { smooth_mls(need_cloud(d, "cloud.mls"), o, scale_of(d)); }
};

struct DequantizeStage : Stage {
  DequantizeOptions o;
  void bind(Binder& b) override { bind_options(b, o); }
  void run(Data& d, RunContext&) override {
    const QuantizationReport r = dequantize_depth(need_cloud(d, "cloud.dequantize"), o);
    char buf[256];
    if (!r.organized) {
      details = "not an organized cloud: nothing to do";
    } else {
      std::snprintf(buf, sizeof buf, "%zu distinct depths over %zu points, %.0f%% of neighbouring pixels equal, median step %.3g: %s",
                    r.distinct_depths, r.valid_points, 100.0 * r.equal_neighbours, r.median_step,
                    r.applied ? (std::to_string(r.moved) + " points moved onto ramps between the depth levels").c_str()
                              : (r.quantized ? "quantized, left as is" : "not quantized, left as is"));
      details = buf;
    }
    if (!r.organized) {  // nothing was measured
      decision_text = {{"organized", "no"}};
      return;
    }
    decision_text = {{"quantized", r.quantized ? "yes" : "no"}, {"dequantized", r.applied ? "yes" : "no"}};
    decision_numbers = {{"distinct_depths", static_cast<double>(r.distinct_depths)},
                        {"equal_neighbours", r.equal_neighbours},
                        {"median_step", r.median_step},
                        {"moved", static_cast<double>(r.moved)}};
    if (r.applied) d.scale.reset();
  }
};

std::vector<PointCloud> views_of(const std::vector<const Data*>& inputs, const char* stage) {
  std::vector<PointCloud> views;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (!inputs[i]->cloud)
      throw InputError(std::string(stage) + ": input " + std::to_string(i + 1) + " is not a point cloud (combine clouds before meshing)");
    views.push_back(*inputs[i]->cloud);
  }
  return views;
}

struct MergeStage : Stage {
  void bind(Binder&) override {}
  [[nodiscard]] bool takes_many_inputs() const override { return true; }
  void run(Data&, RunContext&) override { throw InputError("cloud.merge needs 'inputs': the tags of the views to merge"); }
  void run_many(const std::vector<const Data*>& inputs, Data& out, RunContext&) override {
    const std::vector<PointCloud> views = views_of(inputs, "cloud.merge");
    out.cloud = merge_views(views);
    details = std::to_string(views.size()) + " views, " + std::to_string(out.cloud->size()) + " points";
  }
};

struct RegisterStage : Stage {
  RegisterOptions o;
  void bind(Binder& b) override { bind_options(b, o); }
  [[nodiscard]] bool takes_many_inputs() const override { return true; }
  void run(Data&, RunContext&) override { throw InputError("cloud.register needs 'inputs': the tags of the views to align"); }
  void run_many(const std::vector<const Data*>& inputs, Data& out, RunContext& ctx) override {
    std::vector<PointCloud> views = views_of(inputs, "cloud.register");
    const std::vector<ViewAlignment> a = register_views(views, o);
    out.cloud = merge_views(views);
    char buf[200];
    details = std::to_string(views.size()) + " views aligned to the first:";
    for (std::size_t k = 1; k < a.size(); ++k) {
      std::snprintf(buf, sizeof buf, " view %zu moved %.3g deg and %.3g, RMS %.3g, overlap %.0f%%%s;", k + 1, a[k].rotation_deg,
                    a[k].translation, a[k].rms, 100.0 * a[k].overlap, a[k].converged ? "" : " (not converged)");
      details += buf;
      decision_numbers.push_back({"view" + std::to_string(k + 1) + "_rotation_deg", a[k].rotation_deg});
      decision_numbers.push_back({"view" + std::to_string(k + 1) + "_translation", a[k].translation});
      decision_numbers.push_back({"view" + std::to_string(k + 1) + "_rms", a[k].rms});
      decision_numbers.push_back({"view" + std::to_string(k + 1) + "_overlap", a[k].overlap});
      if (a[k].overlap < 0.2)
        ctx.warnings.push_back("cloud.register: view " + std::to_string(k + 1) + " overlaps the others by only " +
                               std::to_string(static_cast<int>(100.0 * a[k].overlap)) + "%; its pose may be wrong");
    }
  }
};

template <class S>
StageFactory make() {
  return [] { return std::make_unique<S>(); };
}

}  // namespace

void register_cloud_stages(StageRegistry& r) {
  r.add("cloud.crop", make<CropStage>());
  r.add("cloud.voxel", make<VoxelStage>());
  r.add("cloud.outliers", make<OutlierStage>());
  r.add("cloud.normals", make<NormalStage>());
  r.add("cloud.mls", make<MlsStage>());
  r.add("cloud.dequantize", make<DequantizeStage>());
  r.add("cloud.merge", make<MergeStage>());
  r.add("cloud.register", make<RegisterStage>());
}

}  // namespace scanmesh::detail
