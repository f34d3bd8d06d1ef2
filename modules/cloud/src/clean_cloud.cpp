// Cloud clean-up. Outlier removal, normal estimation and MLS use PCL; the voxel grid and the normal
// orientation are written here (attribute averaging and a deterministic propagation order).
#include "scanmesh/clean_cloud.h"

#include <pcl/features/normal_3d_omp.h>
#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/point_types.h>
#include <pcl/surface/mls.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <tuple>
#include <utility>

#include "scanmesh/errors.h"
#include "scanmesh/geometry.h"
#include "scanmesh/neighbourhoods.h"
#include "scanmesh/parallel.h"

namespace scanmesh {
namespace {

std::vector<Vec3> finite_points(const PointCloud& cloud, std::vector<int>* index = nullptr) {
  std::vector<Vec3> pts;
  pts.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (cloud.points[i].allFinite()) {
      pts.push_back(cloud.points[i]);
      if (index) index->push_back(static_cast<int>(i));
    }
  return pts;
}

// The points for PCL, relative to `origin` (local_origin: PCL's floats would round georeferenced
// coordinates to decimetres).
pcl::PointCloud<pcl::PointXYZ>::Ptr to_pcl(const std::vector<Vec3>& pts, const Vec3& origin) {
  auto c = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  c->reserve(pts.size());
  for (const auto& p : pts) {
    const Vec3 q = p - origin;
    c->push_back(pcl::PointXYZ(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z())));
  }
  return c;
}

// Marks removed points: organized clouds keep their grid with NaN holes, others shrink.
void apply_keep(PointCloud& cloud, const std::vector<std::uint8_t>& keep) {
  if (cloud.organized()) {
    const double nan = std::nan("");
    for (std::size_t i = 0; i < cloud.size(); ++i)
      if (!keep[i]) cloud.points[i] = Vec3::Constant(nan);
  } else {
    keep_points(cloud, keep);
  }
}

}  // namespace

void crop(PointCloud& cloud, const CropOptions& o) {
  std::vector<std::uint8_t> keep(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& p = cloud.points[i];
    keep[i] = (p.array() >= o.min.array()).all() && (p.array() <= o.max.array()).all() ? 1 : 0;
  }
  keep_points(cloud, keep);
}

namespace {

// A voxel's integer coordinates and the point in it; sorted by voxel, then by point (the accumulation order).
struct VoxelKey {
  std::int64_t x, y, z;
  std::uint32_t point;
  bool operator<(const VoxelKey& o) const { return std::tie(x, y, z, point) < std::tie(o.x, o.y, o.z, o.point); }
  bool same_voxel(const VoxelKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

std::vector<VoxelKey> voxel_keys(const PointCloud& cloud, double leaf) {
  std::vector<VoxelKey> keys;
  keys.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& p = cloud.points[i];
    if (!p.allFinite()) continue;
    const Vec3 c = (p / leaf).array().floor();
    if (!(c.cwiseAbs().maxCoeff() < 4e18))
      throw InputError("cloud.voxel: a voxel edge of " + std::to_string(leaf) + " is too small for coordinates as large as " +
                       std::to_string(p.cwiseAbs().maxCoeff()));
    keys.push_back({static_cast<std::int64_t>(c.x()), static_cast<std::int64_t>(c.y()), static_cast<std::int64_t>(c.z()),
                    static_cast<std::uint32_t>(i)});
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

std::size_t occupied_voxels(const std::vector<VoxelKey>& keys) {
  std::size_t n = 0;
  for (std::size_t k = 0; k < keys.size(); ++k) n += (k == 0 || !keys[k].same_voxel(keys[k - 1])) ? 1 : 0;
  return n;
}

// The number of occupied voxels of edge `leaf`, for the search of an edge: 21 bits per axis packed into
// one 64-bit key where the cloud (within `bounds`, its finite_box) spans fewer than 2^21 voxels along each
// axis (a quarter of the memory and of the sorting time of the full keys), else from the full keys.
std::size_t occupied_voxels(const PointCloud& cloud, const Box& bounds, double leaf) {
  const Vec3 c0 = (bounds.lo / leaf).array().floor();
  const Vec3 span = (bounds.hi / leaf).array().floor() - c0.array();
  constexpr double kCells = 1 << 21;
  if (!(span.maxCoeff() < kCells)) return occupied_voxels(voxel_keys(cloud, leaf));
  std::vector<std::uint64_t> keys;
  keys.reserve(cloud.size());
  for (const Vec3& p : cloud.points) {
    if (!p.allFinite()) continue;
    // The same floor as voxel_keys, then shifted to start at 0 (clamped against rounding at the ends).
    const Vec3 c = ((p / leaf).array().floor() - c0.array()).cwiseMax(0.0).cwiseMin(kCells - 1);
    keys.push_back((static_cast<std::uint64_t>(c.x()) << 42) | (static_cast<std::uint64_t>(c.y()) << 21) |
                   static_cast<std::uint64_t>(c.z()));
  }
  std::sort(keys.begin(), keys.end());
  return static_cast<std::size_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
}

}  // namespace

VoxelReport voxel_downsample(PointCloud& cloud, const VoxelOptions& o, const CloudScale& scale) {
  VoxelOptions::schema().validate(o);
  if (cloud.size() > std::numeric_limits<std::uint32_t>::max())
    throw InputError("cloud.voxel: more than 2^32 points (" + std::to_string(cloud.size()) + ")");
  VoxelReport r;
  r.before = r.after = static_cast<std::size_t>(std::count_if(cloud.points.begin(), cloud.points.end(), [](const Vec3& p) { return p.allFinite(); }));
  double leaf = o.leaf.resolve(scale.spacing, scale.spacing, scale.diagonal);
  std::vector<VoxelKey> keys;
  if (leaf > 0.0) keys = voxel_keys(cloud, leaf);
  const auto limit = static_cast<std::size_t>(o.max_points);
  const std::size_t count = leaf > 0.0 ? occupied_voxels(keys) : r.before;
  if (limit > 0 && count > limit) {
    if (cloud.organized()) {
      r.limit_skipped_organized = true;
    } else if (scale.spacing > 0.0) {
      // On a surface the count falls with the square of the edge: estimate the edge from the spacing, bracket
      // the limit between an edge whose grid has too many voxels and one whose grid fits, and halve the
      // bracket (geometrically) until its ends are within 2%; the end that fits is used.
      const auto ratio = [&](std::size_t n) { return std::sqrt(static_cast<double>(n) / static_cast<double>(limit)); };
      const Box bounds = finite_box(cloud.points);  // once: every count of the search uses it
      double too_small = leaf;  // 0, or an edge whose count is over the limit
      double fits = 0.0;
      double l = std::max(leaf * 1.02, scale.spacing * ratio(count));
      // Past twice the diagonal every point shares one of at most 8 voxels (those at the origin's corner).
      while (fits == 0.0) {
        const std::size_t n = occupied_voxels(cloud, bounds, l);
        if (n <= limit || l > 2.0 * scale.diagonal) {
          fits = l;
        } else {
          too_small = l;
          l *= std::max(1.02, ratio(n));
        }
      }
      if (too_small == 0.0) {  // the estimate already fits: shrink it until the grid is over the limit
        for (std::size_t n = limit; too_small == 0.0 && fits > 1e-9 * scale.diagonal;) {
          const double s = fits / std::max(1.02, 1.0 / ratio(std::max<std::size_t>(n, 1)));
          n = occupied_voxels(cloud, bounds, s);
          (n > limit ? too_small : fits) = s;
        }
      }
      while (too_small > 0.0 && fits > 1.02 * too_small) {
        const double mid = std::sqrt(too_small * fits);
        (occupied_voxels(cloud, bounds, mid) > limit ? too_small : fits) = mid;
      }
      l = fits;
      keys = voxel_keys(cloud, l);
      leaf = l;
    }
  }
  if (keys.empty()) return r;
  PointCloud out;
  out.sensor_origin = cloud.sensor_origin;
  out.sensor_orientation = cloud.sensor_orientation;
  for (std::size_t k = 0; k < keys.size();) {
    Vec3 p = Vec3::Zero(), n = Vec3::Zero(), c = Vec3::Zero();
    std::size_t e = k;
    for (; e < keys.size() && keys[e].same_voxel(keys[k]); ++e) {
      const std::size_t i = keys[e].point;
      p += cloud.points[i];
      if (cloud.has_normals()) n += cloud.normals[i];
      if (cloud.has_colours()) c += Vec3(cloud.colours[i][0], cloud.colours[i][1], cloud.colours[i][2]);
    }
    const auto m = static_cast<double>(e - k);
    out.points.push_back(p / m);
    if (cloud.has_normals()) out.normals.push_back(n.norm() > 0.0 ? Vec3(n.normalized()) : Vec3::Zero());
    if (cloud.has_colours()) {
      c /= m;
      out.colours.push_back({static_cast<std::uint8_t>(std::lround(c.x())), static_cast<std::uint8_t>(std::lround(c.y())),
                             static_cast<std::uint8_t>(std::lround(c.z()))});
    }
    k = e;
  }
  out.width = static_cast<int>(out.points.size());
  cloud = std::move(out);
  r.after = cloud.size();
  r.leaf = leaf;
  return r;
}

namespace {

void require_surface(const PointCloud& cloud) {
  const std::string problem = surface_problem(cloud);
  if (!problem.empty()) throw InputError(problem + ": there is no surface to find");
}

}  // namespace

void remove_outliers(PointCloud& cloud, const OutlierOptions& o, const CloudScale& scale) {
  OutlierOptions::schema().validate(o);
  if (!(o.std_ratio > 0.0) && !(o.radius.value > 0.0)) return;  // both tests off
  require_surface(cloud);
  std::vector<int> index;
  const std::vector<Vec3> pts = finite_points(cloud, &index);
  if (pts.size() <= static_cast<std::size_t>(o.neighbours)) return;
  auto pc = to_pcl(pts, local_origin(pts));
  std::vector<std::uint8_t> keep(cloud.size(), 0);
  std::vector<std::uint8_t> pass(pts.size(), 1);
  if (o.std_ratio > 0.0) {
    pcl::Indices kept;
    pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor;
    sor.setInputCloud(pc);
    sor.setMeanK(o.neighbours);
    sor.setStddevMulThresh(o.std_ratio);
    sor.filter(kept);
    pass.assign(pts.size(), 0);
    for (auto k : kept) pass[k] = 1;
  }
  const double radius = o.radius.resolve(scale.spacing, scale.spacing, scale.diagonal);
  if (radius > 0.0) {
    pcl::RadiusOutlierRemoval<pcl::PointXYZ> ror;
    ror.setInputCloud(pc);
    ror.setRadiusSearch(radius);
    ror.setMinNeighborsInRadius(o.min_neighbours);
    pcl::Indices rk;
    ror.filter(rk);
    std::vector<std::uint8_t> rpass(pts.size(), 0);
    for (auto k : rk) rpass[k] = 1;
    for (std::size_t i = 0; i < pts.size(); ++i) pass[i] = pass[i] && rpass[i];
  }
  for (std::size_t i = 0; i < pts.size(); ++i) keep[index[i]] = pass[i];
  apply_keep(cloud, keep);
}

void estimate_normals(PointCloud& cloud, const NormalOptions& o) {
  NormalOptions::schema().validate(o);
  if (o.keep && cloud.has_normals()) return;
  require_surface(cloud);
  std::vector<int> index;
  const std::vector<Vec3> pts = finite_points(cloud, &index);
  if (pts.size() < 3) throw InputError("normals: the cloud has fewer than 3 finite points");
  const Vec3 origin = local_origin(pts);
  auto pc = to_pcl(pts, origin);
  pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> ne(static_cast<unsigned>(thread_count()));
  ne.setInputCloud(pc);
  ne.setKSearch(std::min<int>(o.neighbours, static_cast<int>(pts.size()) - 1));
  if (cloud.sensor_origin) {
    const Vec3 s = *cloud.sensor_origin - origin;
    ne.setViewPoint(static_cast<float>(s.x()), static_cast<float>(s.y()), static_cast<float>(s.z()));
  }
  pcl::PointCloud<pcl::Normal> normals;
  ne.compute(normals);
  std::vector<Vec3> n(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto& q = normals[i];
    n[i] = Vec3(q.normal_x, q.normal_y, q.normal_z);
    if (!n[i].allFinite() || n[i].norm() < 0.5) n[i] = Vec3::Zero();
  }
  // Both steps below read each point's nearest neighbours; most clouds need neither (no degenerate
  // neighbourhood, orientation from the sensor), so the table (a second k-nearest search over every point)
  // is built only when one of them runs.
  const bool degenerate = std::any_of(n.begin(), n.end(), [](const Vec3& v) { return v.isZero(); });
  const bool have_hints = cloud.has_normals() && cloud.normals.size() == cloud.size() && cloud.normals_oriented;
  const bool propagate = o.orient && !cloud.sensor_origin && !have_hints;
  const Adjacency knn = degenerate || propagate ? knn_neighbourhoods(pts, std::min<int>(o.neighbours, static_cast<int>(pts.size()) - 1))
                                                : Adjacency{};
  // Points whose neighbourhood was degenerate borrow the nearest valid normal.
  for (std::size_t i = 0; i < pts.size() && degenerate; ++i)
    if (n[i].isZero())
      for (const int* j = knn.begin(i); j != knn.end(i); ++j)
        if (!n[*j].isZero()) {
          n[i] = n[*j];
          break;
        }
  // Normals already in the cloud (from the scanner or its software) tell which side is out: agree with them.
  if (o.orient && have_hints) {
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Vec3& hint = cloud.normals[index[i]];
      if (hint.allFinite() && n[i].dot(hint) < 0.0) n[i] = -n[i];
    }
  }
  if (propagate) {
    // Hoppe-style propagation: grow from the highest point (normal turned up), always taking next the
    // neighbour whose normal is most parallel to an oriented one, flipping it to agree.
    // Connected parts of the kNN graph (treated as undirected), each started at its highest point.
    std::vector<int> part(pts.size(), -1);
    std::vector<int> top;
    {
      std::vector<std::vector<int>> undirected(pts.size());
      for (std::size_t i = 0; i < pts.size(); ++i)
        for (const int* j = knn.begin(i); j != knn.end(i); ++j) {
          undirected[i].push_back(*j);
          undirected[*j].push_back(static_cast<int>(i));
        }
      std::vector<int> stack;
      for (std::size_t s0 = 0; s0 < pts.size(); ++s0) {
        if (part[s0] >= 0) continue;
        const int id = static_cast<int>(top.size());
        top.push_back(static_cast<int>(s0));
        part[s0] = id;
        stack.assign(1, static_cast<int>(s0));
        while (!stack.empty()) {
          const int v = stack.back();
          stack.pop_back();
          if (pts[v].z() > pts[top[id]].z()) top[id] = v;
          for (int w : undirected[v])
            if (part[w] < 0) {
              part[w] = id;
              stack.push_back(w);
            }
        }
      }
    }
    std::vector<std::uint8_t> done(pts.size(), 0);
    using Item = std::tuple<double, int, int>;  // (1 - |n_i . n_j|, j, i): smallest first, ties by index
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    auto push = [&](int i) {
      for (const int* j = knn.begin(i); j != knn.end(i); ++j)
        if (!done[*j]) queue.emplace(1.0 - std::abs(n[i].dot(n[*j])), *j, i);
    };
    for (int t : top) {
      if (n[t].z() < 0.0) n[t] = -n[t];
      done[t] = 1;
      push(t);
      while (!queue.empty()) {
        const auto [cost, j, i] = queue.top();
        queue.pop();
        if (done[j]) continue;
        if (n[i].dot(n[j]) < 0.0) n[j] = -n[j];
        done[j] = 1;
        push(j);
      }
    }
  }
  cloud.normals.assign(cloud.size(), Vec3::Constant(std::nan("")));
  cloud.normals_oriented = o.orient;
  for (std::size_t i = 0; i < pts.size(); ++i) cloud.normals[index[i]] = n[i];
}

void smooth_mls(PointCloud& cloud, const MlsOptions& o, const CloudScale& scale) {
  const double radius = o.radius.resolve(scale.spacing, scale.spacing, scale.diagonal);
  if (!(radius > 0.0)) return;
  require_surface(cloud);
  std::vector<int> index;
  const std::vector<Vec3> pts = finite_points(cloud, &index);
  const Vec3 origin = local_origin(pts);
  auto pc = to_pcl(pts, origin);
  pcl::MovingLeastSquares<pcl::PointXYZ, pcl::PointXYZ> mls;
  mls.setInputCloud(pc);
  mls.setSearchRadius(radius);
  mls.setPolynomialOrder(o.polynomial_order);
  mls.setNumberOfThreads(1);  // PCL's MLS output order depends on thread scheduling otherwise
  mls.setProjectionMethod(pcl::MLSResult::SIMPLE);
  pcl::PointCloud<pcl::PointXYZ> out;
  mls.process(out);
  const auto& corr = mls.getCorrespondingIndices();
  if (!corr || corr->indices.size() != out.size()) return;
  for (std::size_t k = 0; k < out.size(); ++k) {
    const auto& q = out[k];
    cloud.points[index[corr->indices[k]]] = Vec3(q.x, q.y, q.z) + origin;
  }
}

}  // namespace scanmesh
