// scan.virtual: a clean mesh -> the merged cloud of a virtual depth scanner's views.
#include "scanmesh/neighbourhoods.h"
#include "scanmesh/combine_views.h"
#include "scanmesh/virtual_scan.h"
#include "stage.h"

namespace scanmesh::detail {
namespace {

struct ScanStage : Stage {
  VirtualScanOptions o;
  void bind(Binder& b) override { bind_options(b, o); }
  void run(Data& d, RunContext&) override {
    d.cloud = merge_views(virtual_scan(need_mesh(d, "scan.virtual"), o));
    d.mesh.reset();
    d.before.reset();
    d.scale = measure_scale(*d.cloud);
    d.seed = o.seed;
  }
};

}  // namespace

void register_scan_stages(StageRegistry& r) {
  r.add("scan.virtual", [] { return std::make_unique<ScanStage>(); });
}

}  // namespace scanmesh::detail
