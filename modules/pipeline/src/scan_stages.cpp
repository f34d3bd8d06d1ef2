// The stage families that need PCL, VTK or OpenCV, added to the registry on request (the light command-line
// tool runs its pipelines without them).
#include "stage.h"

namespace scanmesh {

void register_scan_stages() {
  detail::StageRegistry& r = detail::stage_registry();
  detail::register_cloud_stages(r);
  detail::register_mesh_stages(r);
  detail::register_virtual_scan_stages(r);
  detail::register_report_stages(r);
}

}  // namespace scanmesh
