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

const CloudScale& scale_of(Data& d) {
  if (!d.scale) {
    if (!d.cloud) throw InputError("this stage needs a point cloud, but the pipeline has none at this point");
    d.scale = measure_scale(*d.cloud);
  }
  return *d.scale;
}

PointCloud& need_cloud(Data& d, const char* stage) {
  if (!d.cloud) throw InputError(std::string(stage) + " needs a point cloud, but the pipeline has none at this point");
  return *d.cloud;
}

Mesh& need_mesh(Data& d, const char* stage) {
  if (!d.mesh) throw InputError(std::string(stage) + " needs a mesh, but the pipeline has none at this point (mesh the cloud first)");
  return *d.mesh;
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
