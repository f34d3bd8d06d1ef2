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
  std::string columns;
  bool viewpoint_pose = false;
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();
  static const Schema<ReaderOptions>& schema() {
    static const Schema<ReaderOptions> s =
        Schema<ReaderOptions>()
            .text("filename", &ReaderOptions::filename, "file",
                  "Mesh (.obj .off .ply .stl) or cloud (.pcd .ply .xyz .txt .csv .pts) to read.")
            .text("columns", &ReaderOptions::columns, "column list",
                  "Text clouds: what each column holds, e.g. x,y,z,i,r,g,b (nx ny nz normals, r g b colours, i intensity "
                  "and _ skipped); empty = from the header line, else sniffed from the values.")
            .flag("viewpoint_pose", &ReaderOptions::viewpoint_pose,
                  "Clouds: the points are in the sensor's frame and the file's VIEWPOINT is the sensor's pose; move "
                  "them into the common frame (to merge views).")
            .matrix4("transform", &ReaderOptions::transform, "rigid transform",
                     "Moves what is read (after viewpoint_pose): a 4x4 matrix, row by row, e.g. a view's pose from "
                     "registration software.");
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
    d = Data{};  // a reader starts a new branch of the pipeline
    Eigen::Isometry3d t;
    t.matrix() = o.transform;
    if (!holds_cloud(o.filename)) {
      d.mesh = read_mesh(o.filename, &ctx.warnings);
      if (!o.transform.isIdentity())
        for (Vec3& p : d.mesh->positions) p = t * p;
      return;
    }
    CloudReadOptions ro;
    ro.columns = o.columns;
    d.cloud = read_cloud(o.filename, &ctx.warnings, ro);
    if (o.viewpoint_pose) {
      if (!d.cloud->sensor_origin) throw InputError(o.filename + ": viewpoint_pose: the file gives no VIEWPOINT");
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = d.cloud->sensor_orientation;
      pose.translation() = *d.cloud->sensor_origin;
      d.cloud->sensor_origin = Vec3::Zero();
      d.cloud->sensor_orientation.setIdentity();
      transform_cloud(*d.cloud, pose);
    }
    if (!o.transform.isIdentity()) transform_cloud(*d.cloud, t);
    if (const std::size_t copies = merge_copies(*d.cloud); copies > 0)
      details = d.cloud->organized() ? std::to_string(copies) + " pixels at positions other pixels share (a 'no return' marker) left as holes"
                                     : std::to_string(copies) + " copies of points merged (the first of each position kept)";
    d.scale = measure_scale(*d.cloud);
    if (ctx.report) {  // several readers (views): their points add up; spacing and extent are the first's
      const bool first = ctx.report->input_points == 0;
      ctx.report->input_points += d.cloud->finite_count();
      if (!first) return;
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
      ctx.outputs->write_with(o.filename, [&](const ByteSink& sink) { encode_mesh(*d.mesh, ext, w, sink); });
    } else if (d.cloud) {
      if (d.cloud->finite_count() == 0) throw InputError("nothing to write: the cloud has no points");
      ctx.outputs->write_with(o.filename, [&](const ByteSink& sink) { encode_cloud(*d.cloud, ext == ".pcd" ? ".pcd" : ".ply", sink); });
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
