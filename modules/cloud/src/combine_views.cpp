// Merging views, and refining their poses with PCL's ICP first (see combine_views.h).
// GCC 12 warns (-Warray-bounds) inside PCL's registration templates and Eigen's umeyama, which read a
// 3-float vector with a 4-float SSE load: a false positive in third-party code. The warning is placed at
// the templates' lines, and Eigen's come in with the first header, hence the switch before it.
#pragma GCC diagnostic ignored "-Warray-bounds"
#include "scanmesh/combine_views.h"

#include <pcl/features/normal_3d.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>

#include <algorithm>
#include <cmath>

#include "scanmesh/clean_cloud.h"
#include "scanmesh/errors.h"
#include "scanmesh/neighbourhoods.h"

namespace scanmesh {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

std::vector<Vec3> finite(const PointCloud& c) {
  std::vector<Vec3> out;
  out.reserve(c.size());
  for (const Vec3& p : c.points)
    if (p.allFinite()) out.push_back(p);
  return out;
}

// Points thinned to about one per `leaf` cube (voxel centroids), so ICP costs the same on dense scans.
std::vector<Vec3> thinned(const std::vector<Vec3>& pts, double leaf) {
  PointCloud c;
  c.points = pts;
  c.width = static_cast<int>(pts.size());
  voxel_downsample(c, VoxelOptions{Length::absolute(leaf)}, CloudScale{leaf, leaf});
  return c.points;
}

// The points for PCL relative to `origin` (its floats would round georeferenced coordinates to decimetres).
pcl::PointCloud<pcl::PointXYZ>::Ptr plain(const std::vector<Vec3>& pts, const Vec3& origin) {
  auto out = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const Vec3& p : pts) {
    const Vec3 q = p - origin;
    out->push_back(pcl::PointXYZ(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z())));
  }
  return out;
}

pcl::PointCloud<pcl::PointNormal>::Ptr with_normals(const std::vector<Vec3>& pts, const Vec3& origin) {
  const auto xyz = plain(pts, origin);
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(xyz);
  ne.setKSearch(std::min<int>(15, static_cast<int>(pts.size()) - 1));
  pcl::PointCloud<pcl::Normal> normals;
  ne.compute(normals);
  auto out = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    pcl::PointNormal q;
    q.x = xyz->points[i].x;
    q.y = xyz->points[i].y;
    q.z = xyz->points[i].z;
    const auto& n = normals[i];
    const bool ok = std::isfinite(n.normal_x) && std::isfinite(n.normal_y) && std::isfinite(n.normal_z);
    q.normal_x = ok ? n.normal_x : 0.0f;
    q.normal_y = ok ? n.normal_y : 0.0f;
    q.normal_z = ok ? n.normal_z : 1.0f;
    out->push_back(q);
  }
  return out;
}

// One ICP run from `guess` with the given correspondence distance; returns the new estimate. Both views
// go to PCL relative to `origin`, and the transforms (guess and result) are in that frame. `coarse`
// runs point-to-point ICP for at most `iterations` steps instead of o.method.
Eigen::Matrix4f align(const std::vector<Vec3>& source, const std::vector<Vec3>& target, const Vec3& origin, const RegisterOptions& o,
                      bool coarse, int iterations, double distance, const Eigen::Matrix4f& guess, bool& converged) {
  auto run = [&](auto& icp, const auto& from, const auto& to) {
    icp.setInputSource(from);
    icp.setInputTarget(to);
    icp.setMaxCorrespondenceDistance(distance);
    icp.setMaximumIterations(iterations);
    icp.setTransformationEpsilon(1e-10);
    typename std::decay_t<decltype(*from)> out;
    icp.align(out, guess);
    converged = icp.hasConverged();
    return icp.getFinalTransformation();
  };
  if (coarse) {
    pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
    return run(icp, plain(source, origin), plain(target, origin));
  }
  if (o.method == RegisterMethod::generalized) {
    pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
    return run(icp, plain(source, origin), plain(target, origin));
  }
  pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> icp;
  // Symmetric point-to-plane (Rusinkiewicz 2019): both views' normals, a wider basin than one-sided
  // point-to-plane (which slid 3 spacings along flat faces of Fandisk in the test).
  icp.setUseSymmetricObjective(true);
  icp.setEuclideanFitnessEpsilon(1e-14);
  return run(icp, with_normals(source, origin), with_normals(target, origin));
}

}  // namespace

PointCloud merge_views(const std::vector<PointCloud>& views) {
  PointCloud out;
  bool normals = !views.empty(), colours = !views.empty(), sensors = !views.empty(), oriented = true;
  for (const PointCloud& v : views) {
    normals = normals && v.has_normals();
    colours = colours && v.has_colours();
    sensors = sensors && v.sensor_origin.has_value();
    oriented = oriented && v.normals_oriented;
  }
  for (const PointCloud& v : views)
    for (std::size_t i = 0; i < v.size(); ++i) {
      const Vec3& p = v.points[i];
      if (!p.allFinite()) continue;
      out.points.push_back(p);
      if (normals) out.normals.push_back(v.normals[i]);
      else if (sensors) out.normals.push_back((*v.sensor_origin - p).normalized());
      if (colours) out.colours.push_back(v.colours[i]);
    }
  out.width = static_cast<int>(out.points.size());
  out.normals_oriented = normals ? oriented : sensors;
  return out;
}

std::vector<ViewAlignment> register_views(std::vector<PointCloud>& views, const RegisterOptions& o) {
  RegisterOptions::schema().validate(o);
  std::vector<ViewAlignment> result(views.size());
  if (views.empty()) return result;
  std::vector<Vec3> model = finite(views[0]);
  // One origin for every view, from the first (which stays where it is): PCL works relative to it.
  const Vec3 origin = local_origin(model);
  if (model.size() < 10) throw InputError("register: view 1 has fewer than 10 points");
  for (std::size_t k = 1; k < views.size(); ++k) {
    const std::vector<Vec3> view = finite(views[k]);
    if (view.size() < 10) throw InputError("register: view " + std::to_string(k + 1) + " has fewer than 10 points");
    PointCloud both;
    both.points = model;
    both.points.insert(both.points.end(), view.begin(), view.end());
    const CloudScale scale = measure_scale(both);
    const double spacing = scale.spacing;
    const std::vector<Vec3> target = thinned(model, 1.5 * spacing), source = thinned(view, 1.5 * spacing);
    double distance = std::max(o.max_distance.resolve(spacing, spacing, scale.diagonal), 2.0 * spacing);
    Eigen::Matrix4f t = Eigen::Matrix4f::Identity();  // in the frame centred on `origin`
    ViewAlignment& a = result[k];
    // The coarse levels move the view with point-to-point ICP, a few steps each: from a pose 5 degrees off,
    // point-to-plane (symmetric or not) slid a partly overlapping view of Fandisk 12-15 degrees off at 7
    // of 8 placements of the scene (the voxel grid that thins the views falls differently), point-to-point
    // brought all 8 to within 0.2 degrees; the last level, at two spacings, refines with o.method.
    while (true) {
      const bool fine = distance <= 2.0 * spacing;
      t = align(source, target, origin, o, !fine, fine ? o.iterations : std::max(5, o.iterations / 10), distance, t, a.converged);
      if (fine) break;
      distance = std::max(distance / 3.0, 2.0 * spacing);
    }
    // Back to the views' own frame: p -> origin + T (p - origin).
    Eigen::Isometry3d local;
    local.matrix() = t.cast<double>();
    a.correction = Eigen::Translation3d(origin) * local * Eigen::Translation3d(-origin);
    a.rotation_deg = Eigen::AngleAxisd(a.correction.linear()).angle() * kRadToDeg;
    a.translation = a.correction.translation().norm();
    transform_cloud(views[k], a.correction);
    const std::vector<Vec3> moved = finite(views[k]);
    const std::vector<double> d = nearest_point_distances(model, moved);
    double sum = 0.0;
    std::size_t matched = 0;
    for (double x : d)
      if (x <= 2.0 * spacing) {
        sum += x * x;
        ++matched;
      }
    a.rms = matched ? std::sqrt(sum / static_cast<double>(matched)) : 0.0;
    a.overlap = static_cast<double>(matched) / static_cast<double>(moved.size());
    model.insert(model.end(), moved.begin(), moved.end());
  }
  return result;
}

}  // namespace scanmesh
