#include "scanmesh/point_cloud.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

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

namespace {

// Where most of the finite points are: the coordinate-wise median of up to 100,000 of them (evenly
// strided, so deterministic) and the radius around it holding 90% of that sample; n = 0 if none.
struct Bulk {
  Vec3 centre = Vec3::Zero();
  double radius = 0.0;
  std::size_t n = 0;
};

Bulk bulk_of(const std::vector<Vec3>& points) {
  std::vector<Vec3> sample;
  const std::size_t stride = std::max<std::size_t>(1, points.size() / 100000);
  for (std::size_t i = 0; i < points.size(); i += stride)
    if (points[i].allFinite()) sample.push_back(points[i]);
  Bulk b;
  b.n = sample.size();
  if (sample.empty()) return b;
  std::vector<double> v(sample.size());
  for (int c = 0; c < 3; ++c) {
    for (std::size_t i = 0; i < sample.size(); ++i) v[i] = sample[i][c];
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    b.centre[c] = v[v.size() / 2];
  }
  for (std::size_t i = 0; i < sample.size(); ++i) v[i] = (sample[i] - b.centre).norm();
  const auto k = static_cast<long>((v.size() * 9) / 10);
  std::nth_element(v.begin(), v.begin() + k, v.end());
  b.radius = v[static_cast<std::size_t>(k)];
  return b;
}

// Count, mean, summed outer products about the mean and largest coordinate offset from it of the finite
// points that `take` accepts.
struct Spread {
  std::size_t n = 0;
  Vec3 mean = Vec3::Zero();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  double extent = 0.0;
};

template <class Take>
Spread spread_of(const std::vector<Vec3>& points, Take take) {
  Spread r;
  for (const Vec3& p : points)
    if (p.allFinite() && take(p)) {
      r.mean += p;
      ++r.n;
    }
  if (r.n == 0) return r;
  r.mean /= static_cast<double>(r.n);
  for (const Vec3& p : points)
    if (p.allFinite() && take(p)) {
      const Vec3 d = p - r.mean;
      r.cov += d * d.transpose();
      r.extent = std::max(r.extent, d.cwiseAbs().maxCoeff());
    }
  return r;
}

// Eigenvalues (ascending) of a spread's covariance.
Vec3 spread_eigenvalues(const Spread& s) {
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(s.cov / static_cast<double>(s.n)).eigenvalues();
}

}  // namespace

Vec3 local_origin(const std::vector<Vec3>& points) {
  const Box b = finite_box(points);
  if (b.empty()) return Vec3::Zero();
  const Vec3 centre = 0.5 * (b.lo + b.hi);
  // A few points far from the rest (a sensor's glitch at 1e9) would put the box's centre so far from
  // the scan that single precision rounds the scan itself away; then the scan's own middle is the origin.
  const Bulk bulk = bulk_of(points);
  return (centre - bulk.centre).norm() > 1e3 * bulk.radius && bulk.radius > 0.0 ? bulk.centre : centre;
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

std::vector<std::uint32_t> first_copies(const std::vector<Vec3>& p, std::size_t crowd) {
  // Positions are hashed, the points split by the hash's top bits into buckets of a few thousand (a
  // counting sort, which keeps index order within each bucket), and each bucket deduplicated with a table
  // that fits the cache; coordinates are compared only where hashes agree. A sort of a scan's millions of
  // points, or one table over all of them, took seconds.
  const std::size_t n = p.size();
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("first_copies: more than 2^32 points (" + std::to_string(n) + ")");
  auto bits = [](double v) {
    std::uint64_t b = 0;
    const double w = v == 0.0 ? 0.0 : v;  // -0 and +0 are one position
    std::memcpy(&b, &w, sizeof b);
    return b;
  };
  auto mix = [](std::uint64_t h) {  // splitmix64's finalizer
    h ^= h >> 30, h *= 0xbf58476d1ce4e5b9ULL;
    h ^= h >> 27, h *= 0x94d049bb133111ebULL;
    return h ^ (h >> 31);
  };
  struct Entry {
    std::uint64_t hash;
    std::uint32_t index;
  };
  int bucket_bits = 0;
  while (bucket_bits < 16 && (n >> bucket_bits) > 4096) ++bucket_bits;
  const std::size_t buckets = std::size_t{1} << bucket_bits;
  auto hash = [&](const Vec3& q) { return mix(mix(mix(bits(q.x())) ^ bits(q.y())) ^ bits(q.z())); };
  auto bucket = [&](std::uint64_t h) { return bucket_bits == 0 ? std::size_t{0} : static_cast<std::size_t>(h >> (64 - bucket_bits)); };
  std::vector<std::size_t> start(buckets + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (p[i].allFinite()) ++start[bucket(hash(p[i])) + 1];
  for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
  std::vector<Entry> entries(start[buckets]);  // hashed twice rather than stored: fresh memory is slow
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      if (p[i].allFinite()) {
        const std::uint64_t h = hash(p[i]);
        entries[fill[bucket(h)]++] = {h, static_cast<std::uint32_t>(i)};
      }
  }
  std::vector<std::uint32_t> first;  // allocated at the first copy found
  bool any = false;
#pragma omp parallel
  {
    std::vector<std::uint32_t> table;  // slot -> 1 + position in the bucket of the first point there
    std::vector<std::pair<std::uint32_t, std::uint32_t>> found;  // (copy, first)
#pragma omp for schedule(dynamic, 16)
    for (long b = 0; b < static_cast<long>(buckets); ++b) {
      const Entry* e = entries.data() + start[b];
      const std::size_t m = start[b + 1] - start[b];
      std::size_t slots = 16;
      while (slots < 2 * m) slots *= 2;
      table.assign(slots, 0);
      for (std::size_t k = 0; k < m; ++k) {
        std::size_t s = e[k].hash & (slots - 1);
        for (; table[s] != 0; s = (s + 1) & (slots - 1)) {
          const Entry& f = e[table[s] - 1];
          if (f.hash == e[k].hash && p[f.index] == p[e[k].index]) break;
        }
        if (table[s] != 0)
          found.emplace_back(e[k].index, e[table[s] - 1].index);
        else
          table[s] = static_cast<std::uint32_t>(k + 1);
      }
    }
    // Each point is in one bucket only, so the threads write different entries.
#pragma omp critical(scanmesh_first_copies)
    if (!found.empty() && !any) {
      any = true;
      first.resize(n);
      for (std::size_t i = 0; i < n; ++i) first[i] = static_cast<std::uint32_t>(i);
    }
#pragma omp barrier
    for (const auto& [copy, f] : found) first[copy] = f;
  }
  if (first.empty() || crowd <= 2) return first;
  std::vector<std::uint32_t> copies(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (first[i] != i && ++copies[first[i]] + 1 >= crowd) return first;
  return {};
}

CopyGroups group_copies(const std::vector<std::uint32_t>& first) {
  const std::size_t n = first.size();
  CopyGroups c;
  c.group_of.resize(n);
  c.start.assign(1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (first[i] == i) {
      c.group_of[i] = static_cast<int>(c.start.size() - 1);
      c.start.push_back(0);
    } else {
      c.group_of[i] = c.group_of[first[i]];  // first[i] < i: grouped already
    }
    ++c.start[static_cast<std::size_t>(c.group_of[i]) + 1];
  }
  for (std::size_t g = 1; g < c.start.size(); ++g) c.start[g] += c.start[g - 1];
  c.members.resize(n);
  std::vector<int> fill(c.start.begin(), c.start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) c.members[static_cast<std::size_t>(fill[static_cast<std::size_t>(c.group_of[i])]++)] = static_cast<int>(i);
  return c;
}

std::size_t merge_copies(PointCloud& cloud) {
  const std::vector<std::uint32_t> first = first_copies(cloud.points);
  if (first.empty()) return 0;
  const std::size_t n = cloud.size();
  std::vector<std::uint8_t> keep(n, 1);
  std::size_t copies = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (first[i] == i) continue;
    keep[i] = 0;
    ++copies;
    // Two pixels of a grid see along different rays, which meet only at the sensor: a position several
    // pixels share is a marker ("no return" written as 0 0 0), the first pixel's too.
    if (cloud.organized() && keep[first[i]]) keep[first[i]] = 0, ++copies;
  }
  if (cloud.organized()) {
    for (std::size_t i = 0; i < n; ++i)
      if (!keep[i]) cloud.points[i] = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  } else {
    keep_points(cloud, keep);
  }
  return copies;
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
  const Spread all = spread_of(cloud.points, [](const Vec3&) { return true; });
  const std::size_t n = all.n;
  const Vec3& mean = all.mean;
  const double extent = all.extent;
  if (n == 0) return "the cloud has no finite points";
  std::ostringstream s;
  if (extent == 0.0) {  // (one point is what the reader leaves of any number of copies)
    s << (n == 1 ? std::string("all points are") : "all " + std::to_string(n) + " points are") << " at one position (" << mean.x() << ", "
      << mean.y() << ", " << mean.z() << ")";
    return s.str();
  }
  // The cloud stages work in single precision on coordinates taken relative to the cloud's centre: below
  // this extent the squared distances between neighbours underflow, and no normal can be estimated.
  if (extent < 1e-15) {
    s << "the " << n << " points span only " << 2.0 * extent << " (scene units), too little for the cloud stages, which work in single "
      << "precision (write the coordinates in a smaller unit, micrometres instead of metres, say)";
    return s.str();
  }
  const Vec3 l = spread_eigenvalues(all);  // ascending
  // Collinear points leave a middle eigenvalue at rounding level only: double rounding gives ~1e-32 of the
  // largest, the single precision PCL's stages work in ~1e-14 (a spread across the line of a millionth
  // of its length). A scanned pole or wire, however thin, is wider than that by its noise.
  if (!(l(1) > 1e-12 * l(2))) {
    // A few far points (a glitch at 1e9) make any scan look like a line: judge the bulk then, the 90%
    // nearest its middle; outlier removal takes the rest.
    const Bulk bulk = bulk_of(cloud.points);
    const Spread near = spread_of(cloud.points, [&](const Vec3& p) { return (p - bulk.centre).norm() <= bulk.radius; });
    if (near.n >= 3) {
      const Vec3 bl = spread_eigenvalues(near);
      if (bl(1) > 1e-12 * bl(2)) return "";
    }
    s << "all " << n << " points lie on one line";
    return s.str();
  }
  return "";
}

}  // namespace scanmesh
