// Meshing with PCL. Conversions to and from PCL types stay in this file.
#include "scanmesh/triangulate.h"

#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/console/print.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/gp3.h>
#include <pcl/surface/organized_fast_mesh.h>
#include <pcl/surface/poisson.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>

#include "scanmesh/errors.h"
#include "scanmesh/neighbourhoods.h"

namespace scanmesh {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

// The points with a usable normal, for PCL relative to `origin` (local_origin: its floats would round
// georeferenced coordinates to decimetres); `index` gets their indices in the cloud.
pcl::PointCloud<pcl::PointNormal>::Ptr with_normals(const PointCloud& cloud, const Vec3& origin, std::vector<int>& index) {
  if (!cloud.has_normals()) throw UsageError("meshing needs normals: run normal estimation (cloud.normals) first");
  auto pc = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3 p = cloud.points[i] - origin;
    const Vec3& n = cloud.normals[i];
    if (!p.allFinite() || !n.allFinite() || n.isZero()) continue;
    pcl::PointNormal q;
    q.x = static_cast<float>(p.x());
    q.y = static_cast<float>(p.y());
    q.z = static_cast<float>(p.z());
    q.normal_x = static_cast<float>(n.x());
    q.normal_y = static_cast<float>(n.y());
    q.normal_z = static_cast<float>(n.z());
    pc->push_back(q);
    index.push_back(static_cast<int>(i));
  }
  if (pc->size() < 3)
    throw InputError("meshing: " + std::to_string(pc->size()) + " of the " + std::to_string(cloud.size()) +
                     " points have a usable normal (finite, not zero), at least 3 are needed" +
                     (cloud.size() < 3 ? std::string(": the cloud is too small to mesh")
                                       : std::string(": a normal needs a plane through the point's neighbours (normal_neighbours), "
                                                     "so a handful of points, or points on one line, have none")));
  return pc;
}

// Keeps the first of points at the same position (PCL's greedy projection meshes nothing around copies
// of a point: a view saved twice came out with no faces at all).
void drop_copies(pcl::PointCloud<pcl::PointNormal>& pc, std::vector<int>& index) {
  std::vector<std::size_t> order(pc.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  auto key = [&](std::size_t k) { return std::make_tuple(pc[k].x, pc[k].y, pc[k].z); };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  std::vector<std::uint8_t> keep(pc.size(), 1);
  for (std::size_t k = 1; k < order.size(); ++k)
    if (key(order[k]) == key(order[k - 1])) keep[order[k]] = 0;
  std::size_t w = 0;
  for (std::size_t k = 0; k < pc.size(); ++k)
    if (keep[k]) {
      pc[w] = pc[k];
      index[w++] = index[k];
    }
  pc.resize(w);
  index.resize(w);
}

// Vertices are the cloud's points listed in `index`, faces from PCL polygons (indices into `index`).
Mesh mesh_from_indices(const PointCloud& cloud, const std::vector<int>& index, const std::vector<pcl::Vertices>& polygons) {
  Mesh m;
  m.positions.reserve(index.size());
  for (int i : index) m.positions.push_back(cloud.points[i]);
  for (const auto& poly : polygons)
    for (std::size_t k = 1; k + 1 < poly.vertices.size(); ++k)
      m.faces.push_back({static_cast<int>(poly.vertices[0]), static_cast<int>(poly.vertices[k]), static_cast<int>(poly.vertices[k + 1])});
  if (cloud.has_colours()) {
    const char* names[3] = {"red", "green", "blue"};
    for (int c = 0; c < 3; ++c) {
      VertexProperty p{names[c], ScalarType::uint8, {}};
      for (int i : index) p.values.push_back(cloud.colours[i][c]);
      m.vertex_properties.push_back(std::move(p));
    }
  }
  return m;
}

}  // namespace

double pixel_pitch(const PointCloud& cloud, const Vec3& eye) {
  std::vector<double> ratios;
  const int w = cloud.width, h = cloud.height;
  const int stride = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(cloud.size()) / 20000.0)));
  for (int r = 0; r + 1 < h; r += stride)
    for (int c = 0; c + 1 < w; c += stride) {
      const Vec3& p = cloud.points[static_cast<std::size_t>(r) * w + c];
      if (!p.allFinite()) continue;
      const double range = (p - eye).norm();
      if (!(range > 0.0)) continue;
      for (const Vec3* q : {&cloud.points[static_cast<std::size_t>(r) * w + c + 1], &cloud.points[static_cast<std::size_t>(r + 1) * w + c]})
        if (q->allFinite()) ratios.push_back((*q - p).norm() / range);
    }
  if (ratios.empty()) return 0.0;
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  return ratios[ratios.size() / 2];
}

Mesh triangulate_gp3(const PointCloud& cloud, const Gp3Options& o, const CloudScale& scale) {
  std::vector<int> index;
  auto pc = with_normals(cloud, local_origin(cloud.points), index);
  drop_copies(*pc, index);
  if (pc->size() < 3) throw InputError("meshing: fewer than 3 distinct points with coordinates and normals");
  const double radius = o.radius.resolve(scale.spacing, scale.spacing, scale.diagonal);
  if (!(radius > 0.0)) throw UsageError("gp3: radius must be > 0");
  auto tree = pcl::make_shared<pcl::search::KdTree<pcl::PointNormal>>();
  tree->setInputCloud(pc);
  pcl::GreedyProjectionTriangulation<pcl::PointNormal> gp3;
  gp3.setSearchRadius(radius);
  gp3.setMu(o.mu);
  gp3.setMaximumNearestNeighbors(o.max_neighbours);
  gp3.setMaximumSurfaceAngle(o.max_surface_angle_deg * kDegToRad);
  gp3.setMinimumAngle(o.min_angle_deg * kDegToRad);
  gp3.setMaximumAngle(o.max_angle_deg * kDegToRad);
  gp3.setNormalConsistency(true);  // the normals are oriented
  gp3.setConsistentVertexOrdering(true);
  gp3.setInputCloud(pc);
  gp3.setSearchMethod(tree);
  std::vector<pcl::Vertices> polygons;
  {
    // Its warnings ("Not enough neighbors are considered ... Consider increasing nnn_") name internals a
    // user cannot set; what they cost (points left out, holes) is measured and reported after meshing.
    const pcl::console::VERBOSITY_LEVEL level = pcl::console::getVerbosityLevel();
    pcl::console::setVerbosityLevel(std::min(level, pcl::console::L_ERROR));
    gp3.reconstruct(polygons);
    pcl::console::setVerbosityLevel(level);
  }
  return mesh_from_indices(cloud, index, polygons);
}

Mesh triangulate_organized(const PointCloud& cloud, const OrganizedOptions& o, const CloudScale& scale) {
  if (!cloud.organized()) throw UsageError("organized meshing needs an organized cloud (a width x height grid); use gp3 or poisson");
  auto pc = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  pc->width = static_cast<std::uint32_t>(cloud.width);
  pc->height = static_cast<std::uint32_t>(cloud.height);
  pc->is_dense = false;
  pc->points.resize(cloud.size());
  const Vec3 origin = local_origin(cloud.points);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3 p = cloud.points[i] - origin;  // NaN holes stay NaN
    pc->points[i] = pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  }
  const Vec3 eye = cloud.sensor_origin.value_or(Vec3::Zero());
  // The longest edge grows with the distance from the sensor, as the pixels' footprint does: max_edge
  // (in spacings) is taken relative to the pixel pitch at each point's distance. The pitch (an angle) is
  // the median over grid neighbours of their distance over their range. PCL's own distance-dependent limit
  // would replace its shadow test, so the limit is applied to the triangles afterwards.
  const double pitch = pixel_pitch(cloud, eye);
  const double spacings = o.max_edge.unit == Length::Unit::spacing ? o.max_edge.value : 0.0;
  const double fixed = spacings > 0.0 ? 0.0 : o.max_edge.resolve(scale.spacing, scale.spacing, scale.diagonal);
  pcl::OrganizedFastMesh<pcl::PointXYZ> ofm;
  ofm.setInputCloud(pc);
  ofm.setTrianglePixelSize(1);
  ofm.setTriangulationType(pcl::OrganizedFastMesh<pcl::PointXYZ>::TRIANGLE_ADAPTIVE_CUT);
  // PCL's tolerance is the angle between an edge and the line of sight below which the edge counts as a
  // shadow (a depth jump): a surface seen more obliquely than max_view_angle.
  ofm.setAngleTolerance(static_cast<float>((90.0 - o.max_view_angle_deg) * kDegToRad));
  ofm.setDistanceTolerance(-1.0f);
  ofm.setViewpoint((eye - origin).cast<float>());
  ofm.storeShadowedFaces(false);
  std::vector<pcl::Vertices> polygons;
  ofm.reconstruct(polygons);
  auto too_long = [&](std::uint32_t a, std::uint32_t b) {
    const Vec3& p = cloud.points[a];
    const Vec3& q = cloud.points[b];
    const double limit = spacings > 0.0 ? spacings * pitch * std::max((p - eye).norm(), (q - eye).norm()) : fixed;
    return (p - q).norm() > limit;
  };
  std::vector<pcl::Vertices> kept;
  kept.reserve(polygons.size());
  for (auto& poly : polygons) {
    bool ok = poly.vertices.size() >= 3;
    for (std::size_t k = 0; ok && k < poly.vertices.size(); ++k) ok = !too_long(poly.vertices[k], poly.vertices[(k + 1) % poly.vertices.size()]);
    if (ok) kept.push_back(std::move(poly));
  }
  polygons = std::move(kept);
  // Keep only the finite points that faces use, renumbered in grid order.
  std::vector<int> index, remap(cloud.size(), -1);
  for (const auto& poly : polygons)
    for (auto v : poly.vertices) remap[v] = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (remap[i] == 0) {
      remap[i] = static_cast<int>(index.size());
      index.push_back(static_cast<int>(i));
    }
  for (auto& poly : polygons)
    for (auto& v : poly.vertices) v = static_cast<decltype(v)>(remap[v]);
  return mesh_from_indices(cloud, index, polygons);
}

int poisson_depth_for(const PointCloud& cloud, const CloudScale& scale) {
  // Octree cells about one point spacing wide over the cloud's largest extent, within [5, 10].
  const Box box = finite_box(cloud.points);
  const double extent = (box.hi - box.lo).maxCoeff();  // -inf for an empty box
  if (!(extent > 0.0) || !(scale.spacing > 0.0)) return 8;
  return std::clamp(static_cast<int>(std::ceil(std::log2(extent / scale.spacing))), 5, 10);
}

namespace {

// PCL's Poisson prints its marching cubes' complaints ("Vertex pair not in list ...") with printf, on
// stdout, even under --quiet: they go to /dev/null while it runs.
class StdoutSilenced {
 public:
  StdoutSilenced() {
    std::fflush(stdout);
    saved_ = ::dup(STDOUT_FILENO);
    const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (saved_ >= 0 && null >= 0) ::dup2(null, STDOUT_FILENO);
    if (null >= 0) ::close(null);
  }
  ~StdoutSilenced() {
    std::fflush(stdout);
    if (saved_ >= 0) {
      ::dup2(saved_, STDOUT_FILENO);
      ::close(saved_);
    }
  }
  StdoutSilenced(const StdoutSilenced&) = delete;
  StdoutSilenced& operator=(const StdoutSilenced&) = delete;

 private:
  int saved_ = -1;
};

}  // namespace

Mesh triangulate_poisson(const PointCloud& cloud, const PoissonOptions& o, const CloudScale& scale) {
  if (o.depth != 0 && (o.depth < 4 || o.depth > 12))
    throw UsageError("poisson: depth must be 0 (from the point spacing) or in [4, 12]; got " + std::to_string(o.depth));
  std::vector<int> index;
  const Vec3 origin = local_origin(cloud.points);
  auto pc = with_normals(cloud, origin, index);
  pcl::Poisson<pcl::PointNormal> poisson;
  poisson.setDepth(o.depth > 0 ? o.depth : poisson_depth_for(cloud, scale));
  poisson.setThreads(1);  // PCL's threaded Poisson gives a different mesh from run to run (hippo1: 35,531 faces, two md5s)
  poisson.setInputCloud(pc);
  pcl::PolygonMesh out;
  {
    const StdoutSilenced quiet;
    poisson.reconstruct(out);
  }
  pcl::PointCloud<pcl::PointXYZ> verts;
  pcl::fromPCLPointCloud2(out.cloud, verts);
  Mesh m;
  for (const auto& p : verts.points) m.positions.push_back(Vec3(p.x, p.y, p.z) + origin);
  for (const auto& poly : out.polygons)
    for (std::size_t k = 1; k + 1 < poly.vertices.size(); ++k)
      m.faces.push_back({static_cast<int>(poly.vertices[0]), static_cast<int>(poly.vertices[k]), static_cast<int>(poly.vertices[k + 1])});
  if (!o.watertight) {
    const double trim = o.trim_distance.resolve(scale.spacing, scale.spacing, scale.diagonal);
    std::vector<Vec3> input;
    for (int i : index) input.push_back(cloud.points[i]);
    const std::vector<double> d = nearest_point_distances(input, m.positions);
    std::vector<std::uint8_t> far(m.positions.size(), 0);
    for (std::size_t v = 0; v < m.positions.size(); ++v) far[v] = d[v] > trim ? 1 : 0;
    std::vector<Face> kept;
    for (const Face& f : m.faces)
      if (!far[f[0]] && !far[f[1]] && !far[f[2]]) kept.push_back(f);
    m.faces = std::move(kept);
  }
  return m;
}

}  // namespace scanmesh
