#include "scanmesh/virtual_scan.h"

#include <vtkCellArray.h>
#include <vtkGenericCell.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStaticCellLocator.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "scanmesh/errors.h"
#include "scanmesh/geometry.h"
#include "scanmesh/topology.h"

namespace scanmesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Random numbers that depend only on (seed, view, what they are for), so threads cannot change them.
std::mt19937_64 generator(std::uint64_t seed, int view, std::uint32_t purpose) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32), static_cast<std::uint32_t>(view), purpose};
  return std::mt19937_64(seq);
}

// Uniform in [0, 1), the same on every platform (the standard distributions are not).
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// Standard normal value for one pixel of one view.
double pixel_noise(std::uint64_t seed, int view, long pixel) {
  std::mt19937_64 rng = generator(seed, view, static_cast<std::uint32_t>(pixel));
  const double u = 1.0 - unit(rng);
  const double v = unit(rng);
  return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * kPi * v);
}

}  // namespace

std::vector<PointCloud> virtual_scan(const Mesh& mesh, const VirtualScanOptions& o) {
  if (o.views < 1 || o.width < 2 || o.height < 2) throw UsageError("scan: views >= 1 and an image of at least 2 x 2 pixels");
  if (!(o.fov_deg > 1.0 && o.fov_deg < 170.0)) throw UsageError("scan: fov must be in (1, 170) degrees");
  if (!(o.noise >= 0.0)) throw UsageError("scan: noise must be >= 0");
  if (mesh.faces.empty()) throw InputError("scan: the mesh has no faces");

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const auto& p : mesh.positions) points->InsertNextPoint(p.x(), p.y(), p.z());
  // A triangle stored several times is hit once (the locator's bins cannot separate copies: 10,000 copies
  // of one face took 77 s to scan, every ray testing them all).
  vtkNew<vtkCellArray> polys;
  for (int f : distinct_triangles(mesh)) {
    const Face& t = mesh.faces[static_cast<std::size_t>(f)];
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    polys->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetPolys(polys);
  vtkNew<vtkStaticCellLocator> locator;
  locator->SetDataSet(poly);
  locator->BuildLocator();

  Vec3 lo = mesh.positions[0], hi = mesh.positions[0];
  for (const auto& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec3 centre = (lo + hi) / 2.0;
  const double radius = (hi - lo).norm() / 2.0;
  const double half_fov = o.fov_deg * kPi / 360.0;
  const double distance = radius / std::tan(half_fov) * 1.5;  // the object spans about 2/3 of the image
  const double edge = mean_edge_length(mesh, build_topology(mesh));
  const double sigma = o.noise * edge;

  std::vector<PointCloud> views(static_cast<std::size_t>(o.views));
  for (int v = 0; v < o.views; ++v) {
    // Fibonacci lattice directions, tilted so that no view looks exactly along an axis.
    const double golden = kPi * (3.0 - std::sqrt(5.0));
    const double z = o.views == 1 ? 0.3 : 1.0 - 2.0 * (v + 0.5) / o.views;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Vec3 dir = Vec3(r * std::cos(golden * v + 0.3), r * std::sin(golden * v + 0.3), z).normalized();
    const Vec3 eye = centre + distance * dir;
    const Vec3 forward = -dir;
    Vec3 up = std::abs(forward.z()) < 0.9 ? Vec3(0, 0, 1) : Vec3(0, 1, 0);
    const Vec3 right = forward.cross(up).normalized();
    up = right.cross(forward);
    const double tan_x = std::tan(half_fov), tan_y = tan_x * o.height / o.width;

    PointCloud& cloud = views[v];
    cloud.width = o.width;
    cloud.height = o.height;
    cloud.points.assign(static_cast<std::size_t>(o.width) * o.height, Vec3::Constant(std::nan("")));
    cloud.sensor_origin = eye;
    Eigen::Matrix3d rot;
    rot.col(0) = right;
    rot.col(1) = -up;
    rot.col(2) = forward;  // camera frame: x right, y down, z forward
    cloud.sensor_orientation = rot;
    const long pixels = static_cast<long>(o.width) * o.height;
    // Dropout spots: centres from (seed, view), drawn before the rays so that threads cannot change them.
    std::vector<char> dropped;
    if (o.dropouts > 0) {
      dropped.assign(static_cast<std::size_t>(pixels), 0);
      std::mt19937_64 rng = generator(o.seed, v, 0x5d0u);
      const double r = o.dropout_radius;
      for (int i = 0; i < o.dropouts; ++i) {
        const double cx = unit(rng) * o.width;
        const double cy = unit(rng) * o.height;
        const int c0 = std::max(0, static_cast<int>(std::floor(cx - r))), c1 = std::min(o.width - 1, static_cast<int>(std::ceil(cx + r)));
        const int r0 = std::max(0, static_cast<int>(std::floor(cy - r))), r1 = std::min(o.height - 1, static_cast<int>(std::ceil(cy + r)));
        for (int row = r0; row <= r1; ++row)
          for (int col = c0; col <= c1; ++col)
            if ((col + 0.5 - cx) * (col + 0.5 - cx) + (row + 0.5 - cy) * (row + 0.5 - cy) <= r * r)
              dropped[static_cast<std::size_t>(row) * o.width + col] = 1;
      }
    }
#pragma omp parallel
    {
      vtkNew<vtkGenericCell> cell;
#pragma omp for schedule(dynamic, 256)
      for (long k = 0; k < pixels; ++k) {
        if (!dropped.empty() && dropped[static_cast<std::size_t>(k)]) continue;
        const int col = static_cast<int>(k % o.width), row = static_cast<int>(k / o.width);
        const double px = (2.0 * (col + 0.5) / o.width - 1.0) * tan_x;
        const double py = (1.0 - 2.0 * (row + 0.5) / o.height) * tan_y;
        const Vec3 ray = (forward + px * right + py * up).normalized();
        const Vec3 far = eye + ray * (2.0 * distance + 2.0 * radius);
        double a0[3] = {eye.x(), eye.y(), eye.z()}, a1[3] = {far.x(), far.y(), far.z()};
        double t = 0.0, x[3], pcoords[3];
        int sub = 0;
        vtkIdType cell_id = -1;
        if (locator->IntersectWithLine(a0, a1, 0.0, t, x, pcoords, sub, cell_id, cell) == 0) continue;
        const Vec3 hit(x[0], x[1], x[2]);
        const double depth = (hit - eye).norm();
        const double scale = depth / distance;
        cloud.points[k] = hit + ray * (sigma * scale * scale * pixel_noise(o.seed, v, k));
      }
    }
  }
  return views;
}

}  // namespace scanmesh
