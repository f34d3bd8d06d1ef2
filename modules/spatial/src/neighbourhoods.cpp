#include "scanmesh/neighbourhoods.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "flann_index.h"
#include "scanmesh/geometry.h"
#include "scanmesh/parallel.h"

namespace scanmesh {

namespace {

// Consecutive points that lie close together: groups of at most kGroupSize points whose bounding box
// has a diagonal of at most `extent`, split at multiples of `chunk`. Returns the groups' first indices
// and `n` at the end. Depends on the points only (not on the thread count).
constexpr std::size_t kGroupSize = 64;

std::vector<std::size_t> close_groups(const std::vector<Vec3>& points, double extent, std::size_t chunk) {
  std::vector<std::size_t> starts;
  const double e2 = extent * extent;
  std::size_t i = 0;
  while (i < points.size()) {
    starts.push_back(i);
    Vec3 lo = points[i], hi = points[i];
    std::size_t j = i + 1;
    for (; j < points.size() && j - i < kGroupSize && j % chunk != 0; ++j) {
      const Vec3 l = lo.cwiseMin(points[j]), h = hi.cwiseMax(points[j]);
      if ((h - l).squaredNorm() > e2) break;
      lo = l, hi = h;
    }
    i = j;
  }
  starts.push_back(points.size());
  return starts;
}

constexpr std::size_t kBlock = std::size_t{1} << 15;  // rows handed to `take` at a time
// Points sharing a position before the search goes by position: a few copies each (a face stored twice)
// cost the tree little, and the search by position needs memory.
constexpr std::size_t kCrowd = 17;

// radius_rows for points some of which share a position (`first` from first_copies): a k-d tree cannot
// split a position many points share, so every query near it would scan all of them (100,000 copies of
// one face took 20 s). The search runs over the distinct positions instead, and each point's row is
// made from its position's row: the points at those positions, and with a cap the nearest of them,
// equally distant ones by index (the point itself first among its copies).
template <class Take>
void radius_rows_with_copies(const std::vector<Vec3>& points, const std::vector<std::uint32_t>& first, double radius,
                             int max_neighbours, std::size_t* capped, bool spatially_ordered, Take take) {
  const std::size_t n = points.size();
  const CopyGroups groups = group_copies(first);
  const std::vector<int>& at = groups.members;
  const std::vector<int>& at_start = groups.start;
  std::vector<Vec3> distinct(groups.size());
  for (std::size_t g = 0; g < groups.size(); ++g) distinct[g] = points[static_cast<std::size_t>(groups.first_of(g))];
  // With a cap, the cap nearest positions hold at least that many points.
  const Adjacency near = radius_neighbourhoods(distinct, radius, max_neighbours, nullptr, spatially_ordered);
  std::size_t cut = 0;
  std::vector<std::vector<int>> rows(std::min(kBlock, n));
  for (std::size_t start = 0; start < n; start += kBlock) {
    const auto block = static_cast<long>(std::min(kBlock, n - start));
#pragma omp parallel reduction(+ : cut)
    {
      std::vector<std::pair<double, int>> by_distance;  // (squared distance, position)
      std::vector<int> shell;
#pragma omp for schedule(dynamic, 256)
      for (long r = 0; r < block; ++r) {
        const std::size_t i = start + static_cast<std::size_t>(r);
        const auto u = static_cast<std::size_t>(groups.group_of[i]);
        auto& row = rows[static_cast<std::size_t>(r)];
        row.clear();
        std::size_t total = 0;
        for (const int* v = near.begin(u); v != near.end(u); ++v) total += static_cast<std::size_t>(groups.count(static_cast<std::size_t>(*v)));
        if (max_neighbours <= 0 || total <= static_cast<std::size_t>(max_neighbours)) {
          for (const int* v = near.begin(u); v != near.end(u); ++v)
            row.insert(row.end(), at.begin() + at_start[static_cast<std::size_t>(*v)], at.begin() + at_start[static_cast<std::size_t>(*v) + 1]);
          std::sort(row.begin(), row.end());
          continue;
        }
        ++cut;
        by_distance.clear();
        for (const int* v = near.begin(u); v != near.end(u); ++v)
          by_distance.emplace_back((distinct[static_cast<std::size_t>(*v)] - distinct[u]).squaredNorm(), *v);
        std::sort(by_distance.begin(), by_distance.end());
        const auto cap = static_cast<std::size_t>(max_neighbours);
        for (std::size_t a = 0; a < by_distance.size() && row.size() < cap;) {
          std::size_t b = a;  // [a, b): one distance
          std::size_t points_at = 0;
          for (; b < by_distance.size() && by_distance[b].first == by_distance[a].first; ++b)
            points_at += static_cast<std::size_t>(groups.count(static_cast<std::size_t>(by_distance[b].second)));
          const std::size_t need = cap - row.size();
          if (points_at <= need) {
            for (std::size_t k = a; k < b; ++k) {
              const auto v = static_cast<std::size_t>(by_distance[k].second);
              row.insert(row.end(), at.begin() + at_start[v], at.begin() + at_start[v + 1]);
            }
          } else {
            // The lowest indices of this distance (each position's list is ascending), the point itself first.
            shell.clear();
            bool self = false;
            for (std::size_t k = a; k < b; ++k) {
              const auto v = static_cast<std::size_t>(by_distance[k].second);
              const std::size_t m = std::min<std::size_t>(need + 1, static_cast<std::size_t>(groups.count(v)));
              shell.insert(shell.end(), at.begin() + at_start[v], at.begin() + at_start[v] + static_cast<long>(m));
              self = self || v == u;
            }
            std::sort(shell.begin(), shell.end());
            shell.erase(std::remove(shell.begin(), shell.end(), static_cast<int>(i)), shell.end());
            if (self) row.push_back(static_cast<int>(i));
            row.insert(row.end(), shell.begin(), shell.begin() + static_cast<long>(cap - row.size()));
          }
          a = b;
        }
        std::sort(row.begin(), row.end());
      }
    }
    take(start, rows, static_cast<std::size_t>(block));
  }
  if (capped != nullptr) *capped = cut;
}

// The rows of radius_neighbourhoods, handed to `take(first_row, rows, count)` a block at a time (so the
// rows in flight stay small next to the caller's compact table). Each thread searches with its own result
// set and each row's vector keeps its capacity from block to block, so the search allocates nothing once
// it has warmed up (FLANN's batched radiusSearch allocated an index and a distance vector per query and
// scaled worse on two threads).
//
// Points in a spatial order are searched a group at a time: one tree query gathers every point within
// reach of a group of close points (at most 64, spanning at most 3 radii), and each point of the group
// picks its own from those candidates in double precision. That is one tree descent per group instead of
// one per point, and the same rows: a row is the exact set of points within the radius either way. Where
// the per-point search could have cut a row (more than the cap within 1.01 radii) or a group gathers too
// many candidates (thousands of points on one spot), its points take the per-point search.
template <class Take>
void radius_rows(const std::vector<Vec3>& points, double radius, int max_neighbours, std::size_t* capped,
                 bool spatially_ordered, Take take) {
  const std::size_t n = points.size();
  if (const std::vector<std::uint32_t> first = first_copies(points, kCrowd); !first.empty()) {
    radius_rows_with_copies(points, first, radius, max_neighbours, capped, spatially_ordered, take);
    return;
  }
  // Grouped queries gather a few hundred points each: larger leaves, a faster build, the same answers.
  detail::PointTree tree(points, !spatially_ordered, spatially_ordered ? 48 : 12);
  const double r2 = radius * radius;
  const double wide2 = (1.01 * radius) * (1.01 * radius), loose2 = r2 * (1.0 + 1e-9);
  std::size_t cut = 0;
  constexpr std::size_t kMaxCandidates = 2048;
  const std::vector<std::size_t> groups =
      spatially_ordered ? close_groups(points, 3.0 * radius, kBlock) : std::vector<std::size_t>{};
  std::size_t group = 0;  // first group of the block
  std::vector<std::vector<int>> rows(std::min(kBlock, n));
  for (std::size_t start = 0; start < n; start += kBlock) {
    const auto count = static_cast<long>(std::min(kBlock, n - start));
    std::size_t group_end = group;
    while (spatially_ordered && groups[group_end] < start + static_cast<std::size_t>(count)) ++group_end;
#pragma omp parallel reduction(+ : cut)
    {
      // FLANN takes the squared radius as float; search a little wider and decide in double below. With a
      // cap, one more than the cap is asked for, to tell capped rows from full ones.
      detail::PointTree::Nearest nearest(radius * 1.001, max_neighbours > 0 ? max_neighbours + 1 : -1);
      std::vector<std::size_t> found;
      auto search_one = [&](std::size_t i) {
        const Vec3& p = points[i];
        nearest.search(tree, p, found);
        if (max_neighbours > 0 && found.size() > static_cast<std::size_t>(max_neighbours)) {
          // A full row holds the cap + 1 nearest: drop the farthest (ties: the larger index), which is
          // what sorting by (distance, index) and keeping the first `cap` would do, without sorting.
          const auto& d = nearest.distances();
          std::size_t worst = 0;
          for (std::size_t k = 1; k < found.size(); ++k)
            if (d[k] > d[worst] || (d[k] == d[worst] && found[k] > found[worst])) worst = k;
          found[worst] = found.back();
          found.pop_back();
          ++cut;
        }
        auto& row = rows[i - start];
        row.clear();
        for (std::size_t j : found)
          if ((points[j] - p).squaredNorm() <= r2) row.push_back(static_cast<int>(j));
        std::sort(row.begin(), row.end());
      };
      if (!spatially_ordered) {
#pragma omp for schedule(dynamic, 1024)
        for (long r = 0; r < count; ++r) search_one(start + static_cast<std::size_t>(r));
      } else {
        std::vector<std::size_t> candidates;
        std::vector<double> cx, cy, cz, d2;
        std::vector<int> hit;
#pragma omp for schedule(dynamic, 16)
        for (long g = static_cast<long>(group); g < static_cast<long>(group_end); ++g) {
          const std::size_t first = groups[static_cast<std::size_t>(g)], last = groups[static_cast<std::size_t>(g) + 1];
          Vec3 lo = points[first], hi = points[first];
          for (std::size_t i = first + 1; i < last; ++i) lo = lo.cwiseMin(points[i]), hi = hi.cwiseMax(points[i]);
          const Vec3 centre = 0.5 * (lo + hi);
          // Every point within 1.01 radii of a group member lies within this of the centre (FLANN's float
          // comparison made safe by the last factor).
          tree.radius(centre, (0.5 * (hi - lo).norm() + 1.01 * radius) * 1.001, candidates);
          if (candidates.size() > kMaxCandidates) {
            for (std::size_t i = first; i < last; ++i) search_one(i);
            continue;
          }
          // In index order, every row below comes out sorted: one sort per group instead of one per point.
          std::sort(candidates.begin(), candidates.end());
          cx.resize(candidates.size()), cy.resize(candidates.size()), cz.resize(candidates.size());
          for (std::size_t k = 0; k < candidates.size(); ++k) {
            const Vec3& q = points[candidates[k]];
            cx[k] = q.x(), cy[k] = q.y(), cz[k] = q.z();
          }
          const std::size_t m = candidates.size();
          d2.resize(m);
          hit.resize(m);
          for (std::size_t i = first; i < last; ++i) {
            const Vec3& p = points[i];
            auto& row = rows[i - start];
            row.clear();
            const double px = p.x(), py = p.y(), pz = p.z();
            for (std::size_t k = 0; k < m; ++k) {  // vectorized
              const double dx = cx[k] - px, dy = cy[k] - py, dz = cz[k] - pz;
              d2[k] = dx * dx + dy * dy + dz * dz;
            }
            std::size_t hits = 0, near = 0;
            for (std::size_t k = 0; k < m; ++k) {  // without branches: a tenth of the candidates are hits
              hit[hits] = static_cast<int>(k);
              hits += d2[k] <= loose2 ? 1 : 0;
              near += d2[k] <= wide2 ? 1 : 0;
            }
            // Decided by the per-point search's own expression (the sum above may round differently).
            for (std::size_t h = 0; h < hits; ++h) {
              const std::size_t j = candidates[static_cast<std::size_t>(hit[h])];
              if ((points[j] - p).squaredNorm() <= r2) row.push_back(static_cast<int>(j));
            }
            if (max_neighbours > 0 && near > static_cast<std::size_t>(max_neighbours)) search_one(i);
          }
        }
      }
    }
    take(start, rows, static_cast<std::size_t>(count));
    group = group_end;
  }
  if (capped != nullptr) *capped = cut;
}

}  // namespace

Adjacency radius_neighbourhoods(const std::vector<Vec3>& points, double radius, int max_neighbours, std::size_t* capped,
                                bool spatially_ordered) {
  const std::size_t n = points.size();
  Adjacency a;
  a.offsets.assign(n + 1, 0);
  radius_rows(points, radius, max_neighbours, capped, spatially_ordered,
              [&](std::size_t start, const std::vector<std::vector<int>>& found, std::size_t count) {
                for (std::size_t r = 0; r < count; ++r)
                  a.offsets[start + r + 1] = a.offsets[start + r] + static_cast<int>(found[r].size());
                // Room for every row, guessed from the first block's mean size (the vector still grows if short).
                if (start == 0)
                  a.indices.reserve(static_cast<std::size_t>(1.05 * static_cast<double>(a.offsets[count]) / static_cast<double>(count) *
                                                             static_cast<double>(n)) + 16);
                for (std::size_t r = 0; r < count; ++r) a.indices.insert(a.indices.end(), found[r].begin(), found[r].end());
              });
  return a;
}

PackedRows packed_radius_neighbourhoods(const std::vector<Vec3>& points, double radius, int max_neighbours,
                                        std::size_t* capped, bool spatially_ordered) {
  PackedRows a;
  radius_rows(points, radius, max_neighbours, capped, spatially_ordered,
              [&](std::size_t start, const std::vector<std::vector<int>>& found, std::size_t count) {
                a.append_rows(static_cast<int>(start), found.data(), count);
                if (start == 0)  // room for every row, guessed from the first block (still grows if short)
                  a.reserve(points.size(), static_cast<std::size_t>(1.05 * static_cast<double>(a.units()) / static_cast<double>(count) *
                                                                    static_cast<double>(points.size())) + 16);
              });
  return a;
}

Adjacency knn_neighbourhoods(const std::vector<Vec3>& points, int k) {
  const auto n = static_cast<long>(points.size());
  const std::size_t kk = std::min<std::size_t>(static_cast<std::size_t>(std::max(k, 0)) + 1, points.size());
  detail::PointTree tree(points);
  std::vector<std::vector<int>> rows(points.size());
#pragma omp parallel
  {
    std::vector<std::size_t> idx;
    std::vector<double> d2;
#pragma omp for schedule(dynamic, 256)
    for (long i = 0; i < n; ++i) {
      tree.knn(points[i], kk, idx, d2);
      // Order by distance, ties by index, so equal distances cannot reorder between runs.
      std::vector<std::pair<double, std::size_t>> order;
      for (std::size_t j = 0; j < idx.size(); ++j)
        if (idx[j] != static_cast<std::size_t>(i)) order.emplace_back(d2[j], idx[j]);
      std::sort(order.begin(), order.end());
      for (std::size_t j = 0; j < order.size() && static_cast<int>(j) < k; ++j) rows[i].push_back(static_cast<int>(order[j].second));
    }
  }
  Adjacency a;
  a.offsets.assign(points.size() + 1, 0);
  for (std::size_t i = 0; i < rows.size(); ++i) a.offsets[i + 1] = a.offsets[i] + static_cast<int>(rows[i].size());
  for (const auto& r : rows) a.indices.insert(a.indices.end(), r.begin(), r.end());
  return a;
}

std::vector<double> nearest_point_distances(const std::vector<Vec3>& points, const std::vector<Vec3>& queries) {
  std::vector<double> d(queries.size(), std::numeric_limits<double>::infinity());
  if (points.empty()) return d;
  detail::PointTree tree(points);
  const auto n = static_cast<long>(queries.size());
#pragma omp parallel
  {
    std::vector<std::size_t> idx;
    std::vector<double> d2;
#pragma omp for schedule(dynamic, 256)
    for (long i = 0; i < n; ++i) {
      tree.knn(queries[i], 1, idx, d2);
      if (!d2.empty()) d[i] = std::sqrt(d2[0]);
    }
  }
  return d;
}

double mean_nearest_neighbour_distance(const std::vector<Vec3>& points) {
  if (points.size() < 2) return 0.0;
  // One point repeated: every distance is 0 (and a k-d tree cannot split it, so the search would be quadratic).
  if (std::all_of(points.begin(), points.end(), [&](const Vec3& p) { return p == points.front(); })) return 0.0;
  detail::PointTree tree(points);
  // Beyond a million points the mean is taken over every k-th point (each one's nearest neighbour still
  // among all points): a sample that size pins the mean to about 0.1%, and the queries were most of the
  // time spent reading a big cloud.
  constexpr std::size_t kMaxQueries = 1000000;
  const std::size_t stride = (points.size() + kMaxQueries - 1) / kMaxQueries;
  const auto n = static_cast<long>((points.size() + stride - 1) / stride);
  std::vector<double> nearest(static_cast<std::size_t>(n), 0.0);
#pragma omp parallel
  {
    std::vector<std::size_t> idx;
    std::vector<double> d2;
#pragma omp for schedule(dynamic, 256)
    for (long q = 0; q < n; ++q) {
      const std::size_t i = static_cast<std::size_t>(q) * stride;
      // The nearest point at another position: copies of a point (a view saved twice, merged exports)
      // would otherwise make the spacing, and every length measured in it, zero.
      double best = 0.0;
      for (std::size_t k = 2; best == 0.0 && k <= 128; k *= 4) {
        tree.knn(points[i], k, idx, d2);
        for (std::size_t j = 0; j < idx.size(); ++j)
          if (d2[j] > 0.0) {
            best = std::sqrt(d2[j]);
            break;
          }
        if (idx.size() < k) break;  // every point seen
      }
      nearest[q] = best;
    }
  }
  double sum = 0.0;  // fixed order: independent of the thread count
  for (double d : nearest) sum += d;
  return sum / static_cast<double>(nearest.size());
}

}  // namespace scanmesh

namespace scanmesh {

CloudScale measure_scale(const PointCloud& cloud) {
  std::vector<Vec3> pts;
  pts.reserve(cloud.size());
  for (const auto& p : cloud.points)
    if (p.allFinite()) pts.push_back(p);
  CloudScale s;
  s.spacing = mean_nearest_neighbour_distance(pts);
  s.diagonal = bbox_diagonal(pts);
  return s;
}

}  // namespace scanmesh
