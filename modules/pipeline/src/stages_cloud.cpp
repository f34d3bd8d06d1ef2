// cloud.*: point-cloud clean-up stages over clean_cloud.h.
#include <cstdio>

#include "scanmesh/clean_cloud.h"
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
  void run(Data& d, RunContext&) override { voxel_downsample(need_cloud(d, "cloud.voxel"), o, scale_of(d)); }
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
    decision_text = {{"quantized", r.quantized ? "yes" : "no"}, {"dequantized", r.applied ? "yes" : "no"}};
    decision_numbers = {{"distinct_depths", static_cast<double>(r.distinct_depths)},
                        {"equal_neighbours", r.equal_neighbours},
                        {"median_step", r.median_step},
                        {"moved", static_cast<double>(r.moved)}};
    if (r.applied) d.scale.reset();
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
}

}  // namespace scanmesh::detail
