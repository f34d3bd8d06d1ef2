// read and write: files in and out of a pipeline, the format chosen by extension.
#include "scanmesh/cloud_io.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/neighbourhoods.h"
#include "scanmesh/report.h"
#include "stage.h"

namespace scanmesh::detail {
namespace {

struct ReaderOptions {
  std::string filename;
  static const Schema<ReaderOptions>& schema() {
    static const Schema<ReaderOptions> s = Schema<ReaderOptions>().text(
        "filename", &ReaderOptions::filename, "file", "Mesh (.obj .off .ply .stl) or cloud (.pcd .ply .xyz .txt .pts) to read.");
    return s;
  }
};

struct WriterOptions {
  std::string filename;
  bool ascii = false;
  static const Schema<WriterOptions>& schema() {
    static const Schema<WriterOptions> s =
        Schema<WriterOptions>()
            .text("filename", &WriterOptions::filename, "file", "Mesh (.obj .off .ply .stl) or cloud (.ply .pcd) to write.")
            .flag("ascii", &WriterOptions::ascii, "Write PLY and STL as text instead of binary.");
    return s;
  }
};

struct ReaderStage : Stage {
  ReaderOptions o;
  void bind(Binder& b) override { bind_options(b, o); }
  [[nodiscard]] std::vector<std::string> files_read() const override { return {o.filename}; }
  void run(Data& d, RunContext& ctx) override {
    if (!holds_cloud(o.filename)) {
      d.mesh = read_mesh(o.filename, &ctx.warnings);
      return;
    }
    d.cloud = read_cloud(o.filename, &ctx.warnings);
    d.scale = measure_scale(*d.cloud);
    if (ctx.report) {
      ctx.report->input_points = d.cloud->finite_count();
      ctx.report->input_spacing = d.scale->spacing;
      ctx.report->input_diagonal = d.scale->diagonal;
    }
  }
};

struct WriterStage : Stage {
  WriterOptions o;
  void bind(Binder& b) override { bind_options(b, o); }
  [[nodiscard]] std::vector<std::string> files_written() const override { return {o.filename}; }
  void run(Data& d, RunContext& ctx) override {
    const std::string ext = lower_extension(o.filename);
    if (d.mesh) {
      if (d.mesh->faces.empty()) throw InputError("nothing to write: the mesh has no faces");
      for (const auto& p : d.mesh->positions)
        if (!p.allFinite()) throw InputError("the mesh has non-finite coordinates; nothing is written");
      WriteOptions w;
      w.binary = !o.ascii;
      ctx.outputs->write(o.filename, encode_mesh(*d.mesh, ext, w));
    } else if (d.cloud) {
      if (d.cloud->finite_count() == 0) throw InputError("nothing to write: the cloud has no points");
      ctx.outputs->write(o.filename, encode_cloud(*d.cloud, ext == ".pcd" ? ".pcd" : ".ply"));
    } else {
      throw InputError("nothing to write: the pipeline produced neither a cloud nor a mesh");
    }
  }
};

}  // namespace

void register_io_stages(StageRegistry& r) {
  r.add("read", [] { return std::make_unique<ReaderStage>(); });
  r.add("write", [] { return std::make_unique<WriterStage>(); });
}

}  // namespace scanmesh::detail
