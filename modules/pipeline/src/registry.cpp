// The stage registry and what every stage shares.
#include "scanmesh/neighbourhoods.h"
#include "stage.h"

namespace scanmesh::detail {

void StageRegistry::add(const std::string& type, StageFactory make) {
  if (!find(type)) types_.emplace_back(type, std::move(make));
}

const StageFactory* StageRegistry::find(const std::string& type) const {
  for (const auto& [name, make] : types_)
    if (name == type) return &make;
  return nullptr;
}

std::vector<std::string> StageRegistry::types() const {
  std::vector<std::string> out;
  for (const auto& [name, make] : types_) out.push_back(name);
  return out;
}

StageRegistry& stage_registry() {
  static StageRegistry r = [] {
    StageRegistry x;
    register_io_stages(x);
    register_denoise_stages(x);
    return x;
  }();
  return r;
}

namespace {

// Why a stage that needs a cloud has none: usually the input was a triangle mesh given to a scan pipeline.
std::string no_cloud(const Data& d, const std::string& stage) {
  if (d.mesh && !d.meshed)
    return stage + " needs a point cloud, but the input is a triangle mesh (" + std::to_string(d.mesh->num_faces()) +
           " faces): the cloud and meshing stages start from points. To denoise a mesh: 'scanmesh denoise MESH OUT --auto' "
           "(or configs/denoise.yaml); to mesh its vertices again, save them as points first (.xyz, or a PLY without faces)";
  return stage + " needs a point cloud, but the pipeline has none at this point";
}

}  // namespace

const CloudScale& scale_of(Data& d) {
  if (!d.scale) {
    if (!d.cloud) throw InputError(no_cloud(d, "this stage"));
    d.scale = measure_scale(*d.cloud);
  }
  return *d.scale;
}

PointCloud& need_cloud(Data& d, const char* stage) {
  if (!d.cloud) throw InputError(no_cloud(d, stage));
  return *d.cloud;
}

Mesh& need_mesh(Data& d, const char* stage) {
  if (d.mesh) return *d.mesh;
  if (d.cloud)
    throw InputError(std::string(stage) + " needs a triangle mesh, but the input is a point cloud (" + std::to_string(d.cloud->size()) +
                     " points) and no stage has meshed it: mesh it first ('scanmesh mesh CLOUD OUT', or the main job, "
                     "configs/scan_to_mesh.yaml)");
  throw InputError(std::string(stage) + " needs a triangle mesh, but the pipeline has none at this point");
}

}  // namespace scanmesh::detail

namespace scanmesh {

std::vector<std::string> stage_types() { return detail::stage_registry().types(); }

std::vector<StageOption> stage_options(const std::string& type) {
  const detail::StageFactory* make = detail::stage_registry().find(type);
  if (!make) throw ConfigError("unknown stage type '" + type + "'; valid: " + detail::join(stage_types()));
  detail::Binder b;
  (*make)()->bind(b);
  return b.fields();
}

std::vector<std::pair<std::string, std::vector<std::string>>> pipeline_schema() {
  std::vector<std::pair<std::string, std::vector<std::string>>> out;
  const detail::StageRegistry& r = detail::stage_registry();
  for (const auto& type : r.types()) {
    detail::Binder b;
    (*r.find(type))()->bind(b);
    out.emplace_back(type, b.names());
  }
  return out;
}

}  // namespace scanmesh
