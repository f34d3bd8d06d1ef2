// cloud.*: point-cloud clean-up stages over clean_cloud.h.
#include "scanmesh/clean_cloud.h"
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
}

}  // namespace scanmesh::detail
