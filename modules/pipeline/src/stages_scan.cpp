// scan.virtual: a clean mesh -> the merged cloud of a virtual depth scanner's views.
#include <filesystem>

#include "scanmesh/cloud_io.h"
#include "scanmesh/neighbourhoods.h"
#include "scanmesh/report.h"
#include "scanmesh/combine_views.h"
#include "scanmesh/virtual_scan.h"
#include "stage.h"

namespace scanmesh::detail {
namespace {

struct ViewFileOptions {
  bool keep_views = false;
  static const Schema<ViewFileOptions>& schema() {
    static const Schema<ViewFileOptions> s = Schema<ViewFileOptions>().flag(
        "keep_views", &ViewFileOptions::keep_views,
        "Also write every view as OUT-view-K.pcd beside the output: an organized cloud with its sensor pose (VIEWPOINT).");
    return s;
  }
};

struct ScanStage : Stage {
  VirtualScanOptions o;
  ViewFileOptions files;
  void bind(Binder& b) override {
    bind_options(b, o);
    bind_options(b, files);
  }
  void run(Data& d, RunContext& ctx) override {
    const std::vector<PointCloud> views = virtual_scan(need_mesh(d, "scan.virtual"), o);
    if (files.keep_views && ctx.report && !ctx.report->output_path.empty()) {
      const std::filesystem::path out(ctx.report->output_path);
      const std::string stem = (out.parent_path() / out.stem()).string();
      for (std::size_t k = 0; k < views.size(); ++k) ctx.outputs->write(stem + "-view-" + std::to_string(k) + ".pcd", encode_cloud(views[k], ".pcd"));
    }
    d.cloud = merge_views(views);
    if (d.cloud->points.empty()) throw InputError("no ray of the virtual scanner hit the mesh");
    d.mesh.reset();
    d.before.reset();
    d.scale = measure_scale(*d.cloud);
    d.seed = o.seed;
  }
};

}  // namespace

void register_virtual_scan_stages(StageRegistry& r) {
  r.add("scan.virtual", [] { return std::make_unique<ScanStage>(); });
}

}  // namespace scanmesh::detail
