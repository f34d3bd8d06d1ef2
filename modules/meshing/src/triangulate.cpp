// Meshing with PCL. Conversions to and from PCL types stay in this file.
#include "scanmesh/triangulate.h"

#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/gp3.h>
#include <pcl/surface/organized_fast_mesh.h>
#include <pcl/surface/poisson.h>

#include <cmath>

#include "scanmesh/errors.h"
#include "scanmesh/neighbourhoods.h"

namespace scanmesh {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

pcl::PointCloud<pcl::PointNormal>::Ptr with_normals(const PointCloud& cloud, std::vector<int>& index) {
  if (!cloud.has_normals()) throw UsageError("meshing needs normals: run normal estimation (cloud.normals) first");
  auto pc = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& p = cloud.points[i];
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
  if (pc->size() < 3) throw InputError("meshing: fewer than 3 points with coordinates and normals");
  return pc;
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

Mesh triangulate_gp3(const PointCloud& cloud, const Gp3Options& o, const CloudScale& scale) {
  std::vector<int> index;
  auto pc = with_normals(cloud, index);
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
  gp3.reconstruct(polygons);
  return mesh_from_indices(cloud, index, polygons);
}

Mesh triangulate_organized(const PointCloud& cloud, const OrganizedOptions& o, const CloudScale& scale) {
  if (!cloud.organized()) throw UsageError("organized meshing needs an organized cloud (a width x height grid); use gp3 or poisson");
  auto pc = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  pc->width = static_cast<std::uint32_t>(cloud.width);
  pc->height = static_cast<std::uint32_t>(cloud.height);
  pc->is_dense = false;
  pc->points.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& p = cloud.points[i];
    pc->points[i] = pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  }
  const double max_edge = o.max_edge.resolve(scale.spacing, scale.spacing, scale.diagonal);
  pcl::OrganizedFastMesh<pcl::PointXYZ> ofm;
  ofm.setInputCloud(pc);
  ofm.setTrianglePixelSize(1);
  ofm.setTriangulationType(pcl::OrganizedFastMesh<pcl::PointXYZ>::TRIANGLE_ADAPTIVE_CUT);
  ofm.setMaxEdgeLength(static_cast<float>(max_edge), 0.0f, 0.0f);
  ofm.setAngleTolerance(static_cast<float>(o.max_view_angle_deg * kDegToRad));
  ofm.setDistanceTolerance(-1.0f);
  if (cloud.sensor_origin) {
    const Vec3& s = *cloud.sensor_origin;
    ofm.setViewpoint(Eigen::Vector3f(static_cast<float>(s.x()), static_cast<float>(s.y()), static_cast<float>(s.z())));
  }
  ofm.storeShadowedFaces(false);
  std::vector<pcl::Vertices> polygons;
  ofm.reconstruct(polygons);
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

Mesh triangulate_poisson(const PointCloud& cloud, const PoissonOptions& o, const CloudScale& scale) {
  if (o.depth < 4 || o.depth > 12) throw UsageError("poisson: depth must be in [4, 12]; got " + std::to_string(o.depth));
  std::vector<int> index;
  auto pc = with_normals(cloud, index);
  pcl::Poisson<pcl::PointNormal> poisson;
  poisson.setDepth(o.depth);
  poisson.setThreads(1);
  poisson.setInputCloud(pc);
  pcl::PolygonMesh out;
  poisson.reconstruct(out);
  pcl::PointCloud<pcl::PointXYZ> verts;
  pcl::fromPCLPointCloud2(out.cloud, verts);
  Mesh m;
  for (const auto& p : verts.points) m.positions.emplace_back(p.x, p.y, p.z);
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

Mesh triangulate(PointCloud& cloud, const MeshMethodOptions& method, const Gp3Options& gp3, const OrganizedOptions& organized,
                 const PoissonOptions& poisson, const CloudScale& scale, std::string* chosen) {
  MeshMethod m = method.method;
  std::string why;
  if (m == MeshMethod::automatic) {
    m = cloud.organized() ? MeshMethod::organized : MeshMethod::gp3;
    why = cloud.organized() ? "organized cloud: organized meshing" : "unorganized cloud: greedy projection";
  }
  if (m == MeshMethod::organized && !cloud.organized())
    throw InputError("organized meshing needs an organized cloud (a width x height grid); this one is a list of " +
                     std::to_string(cloud.size()) + " points (use method gp3 or poisson)");
  if (m != MeshMethod::organized && !cloud.has_normals()) estimate_normals(cloud, NormalOptions{});
  if (chosen)
    *chosen = !why.empty() ? why : m == MeshMethod::gp3 ? "greedy projection" : m == MeshMethod::organized ? "organized meshing" : "Poisson";
  switch (m) {
    case MeshMethod::organized: return triangulate_organized(cloud, organized, scale);
    case MeshMethod::poisson: return triangulate_poisson(cloud, poisson, scale);
    default: return triangulate_gp3(cloud, gp3, scale);
  }
}

}  // namespace scanmesh
