#include "scanmesh/point_cloud.h"

#include <Eigen/Eigenvalues>
#include <sstream>

namespace scanmesh {

std::size_t PointCloud::finite_count() const {
  std::size_t n = 0;
  for (const auto& p : points) n += p.allFinite() ? 1 : 0;
  return n;
}

Box finite_box(const std::vector<Vec3>& points) {
  Box b;
  for (const Vec3& p : points)
    if (p.allFinite()) {
      b.lo = b.lo.cwiseMin(p);
      b.hi = b.hi.cwiseMax(p);
    }
  return b;
}

Vec3 local_origin(const std::vector<Vec3>& points) {
  const Box b = finite_box(points);
  return b.empty() ? Vec3::Zero() : Vec3(0.5 * (b.lo + b.hi));
}

void keep_points(PointCloud& cloud, const std::vector<std::uint8_t>& keep) {
  std::size_t out = 0;
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    if (!keep[i]) continue;
    cloud.points[out] = cloud.points[i];
    if (cloud.has_normals()) cloud.normals[out] = cloud.normals[i];
    if (cloud.has_colours()) cloud.colours[out] = cloud.colours[i];
    ++out;
  }
  cloud.points.resize(out);
  if (cloud.has_normals()) cloud.normals.resize(out);
  if (cloud.has_colours()) cloud.colours.resize(out);
  cloud.width = static_cast<int>(out);
  cloud.height = 1;
}

void drop_non_finite(PointCloud& cloud) {
  std::vector<std::uint8_t> keep(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) keep[i] = cloud.points[i].allFinite() ? 1 : 0;
  keep_points(cloud, keep);
}

void transform_cloud(PointCloud& cloud, const Eigen::Isometry3d& pose) {
  for (Vec3& p : cloud.points)
    if (p.allFinite()) p = pose * p;
  for (Vec3& n : cloud.normals)
    if (n.allFinite()) n = pose.linear() * n;
  if (cloud.sensor_origin) cloud.sensor_origin = pose * *cloud.sensor_origin;
  cloud.sensor_orientation = pose.linear() * cloud.sensor_orientation;
}

std::string surface_problem(const PointCloud& cloud) {
  std::size_t n = 0;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : cloud.points)
    if (p.allFinite()) {
      mean += p;
      ++n;
    }
  if (n == 0) return "the cloud has no finite points";
  mean /= static_cast<double>(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  double extent = 0.0;
  for (const Vec3& p : cloud.points)
    if (p.allFinite()) {
      const Vec3 d = p - mean;
      cov += d * d.transpose();
      extent = std::max(extent, d.cwiseAbs().maxCoeff());
    }
  std::ostringstream s;
  if (extent == 0.0) {
    s << "all " << n << " points are at one position (" << mean.x() << ", " << mean.y() << ", " << mean.z() << ")";
    return s.str();
  }
  // The cloud stages work in single precision on coordinates taken relative to the cloud's centre: below
  // this extent the squared distances between neighbours underflow, and no normal can be estimated.
  if (extent < 1e-15) {
    s << "the " << n << " points span only " << 2.0 * extent << " (scene units), too little for the cloud stages, which work in single "
      << "precision (write the coordinates in a smaller unit, micrometres instead of metres, say)";
    return s.str();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov / static_cast<double>(n));
  const Vec3 l = eig.eigenvalues();  // ascending
  // Collinear points leave a middle eigenvalue at rounding level only: double rounding gives ~1e-32 of the
  // largest, the single precision PCL's stages work in ~1e-14 (a spread across the line of a millionth
  // of its length). A scanned pole or wire, however thin, is wider than that by its noise.
  if (!(l(1) > 1e-12 * l(2))) {
    s << "all " << n << " points lie on one line";
    return s.str();
  }
  return "";
}

}  // namespace scanmesh
