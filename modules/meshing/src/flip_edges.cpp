#include "scanmesh/flip_edges.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_set>
#include <utility>
#include <vector>

namespace scanmesh {
namespace {

std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::min(a, b))) << 32) | static_cast<std::uint32_t>(std::max(a, b));
}

// Whether face f has the directed edge x -> y.
bool runs(const Face& f, int x, int y) {
  for (int k = 0; k < 3; ++k)
    if (f[k] == x && f[(k + 1) % 3] == y) return true;
  return false;
}

}  // namespace

bool should_flip(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double cos_max_bend) {
  // The angle at p of the triangle (p, q, r), robust for obtuse and nearly flat corners.
  auto angle_at = [](const Vec3& p, const Vec3& q, const Vec3& r) {
    const Vec3 u = q - p, v = r - p;
    return std::atan2(u.cross(v).norm(), u.dot(v));
  };
  if (angle_at(c, a, b) + angle_at(d, a, b) <= M_PI + 1e-9) return false;  // Delaunay already
  auto area_normal = [](const Vec3& p, const Vec3& q, const Vec3& r) { return Vec3((q - p).cross(r - p)); };
  const Vec3 n1 = area_normal(a, b, c), n2 = area_normal(b, a, d);
  const Vec3 m1 = area_normal(a, d, c), m2 = area_normal(d, b, c);
  const double l1 = n1.norm(), l2 = n2.norm(), k1 = m1.norm(), k2 = m2.norm();
  if (!(l1 > 0.0 && l2 > 0.0 && k1 > 0.0 && k2 > 0.0)) return false;
  const Vec3 before = n1 / l1 + n2 / l2;
  if (m1.dot(before) <= 0.0 || m2.dot(before) <= 0.0) return false;  // would fold
  // Mostly the new pair bends less than the old one, but not always (about 6% of random non-planar
  // quads that call for a flip, by up to ~27 degrees): beyond the limit it may not bend more.
  return m1.dot(m2) / (k1 * k2) >= std::min(n1.dot(n2) / (l1 * l2), cos_max_bend);
}

FlipReport flip_edges(Mesh& mesh, double max_bend_deg, int max_rounds) {
  FlipReport report;
  const double cos_bend = std::cos(max_bend_deg * M_PI / 180.0);
  const auto nf = mesh.faces.size();
  std::vector<std::pair<std::uint64_t, int>> sides;  // (edge, face) for every face side, sorted by edge
  std::vector<int> faces_at(mesh.positions.size());
  std::vector<char> open_at(mesh.positions.size());
  std::vector<char> touched(nf);
  std::unordered_set<std::uint64_t> made;  // edges this round's flips created
  struct Flip {
    int fa, fb, a, b, c, d;
  };
  std::vector<Flip> done;  // this round's flips
  sides.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      sides.emplace_back(edge_key(mesh.faces[f][k], mesh.faces[f][(k + 1) % 3]), static_cast<int>(f));
      ++faces_at[mesh.faces[f][k]];
    }
  std::sort(sides.begin(), sides.end());
  // A vertex keeps at least three faces if interior, one if on a boundary (or a non-manifold edge). A
  // flip changes no edge's face count but its own (gone) and the new one's (two), so this holds for
  // every round; faces_at is kept up to date as faces are flipped.
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j].first == sides[i].first) ++j;
    if (j - i != 2) open_at[sides[i].first >> 32] = open_at[sides[i].first & 0xffffffffu] = 1;
    i = j;
  }
  auto may_lose_a_face = [&](int v) { return faces_at[v] > (open_at[v] ? 1 : 3); };
  auto find_side = [&](std::uint64_t key) { return std::lower_bound(sides.begin(), sides.end(), std::make_pair(key, -1)); };
  auto exists = [&](std::uint64_t key) {
    const auto it = find_side(key);
    return (it != sides.end() && it->first == key) || made.count(key) > 0;
  };
  // Brings `sides` up to date with this round's flips without sorting it again: each flip takes the two
  // sides of its edge away, adds two of the new edge, and hands one side of each face to the other face.
  // Sides stay in edge order (within an edge, in any order: nothing reads that order).
  auto update_sides = [&]() {
    constexpr std::uint64_t gone = ~std::uint64_t{0};
    auto side_of = [&](std::uint64_t key, int face) {
      auto it = find_side(key);
      while (it->second != face) ++it;  // every flipped face's sides are in the table
      return it;
    };
    std::vector<std::pair<std::uint64_t, int>> added;
    added.reserve(2 * done.size());
    std::vector<std::array<std::vector<std::pair<std::uint64_t, int>>::iterator, 4>> at(done.size());
    for (std::size_t k = 0; k < done.size(); ++k) {  // every side found before any is marked gone
      const Flip& x = done[k];
      at[k] = {side_of(edge_key(x.a, x.b), x.fa), side_of(edge_key(x.a, x.b), x.fb), side_of(edge_key(x.b, x.c), x.fa),
               side_of(edge_key(x.a, x.d), x.fb)};
    }
    for (std::size_t k = 0; k < done.size(); ++k) {
      const Flip& x = done[k];
      at[k][0]->first = at[k][1]->first = gone;
      at[k][2]->second = x.fb;
      at[k][3]->second = x.fa;
      added.emplace_back(edge_key(x.c, x.d), x.fa);
      added.emplace_back(edge_key(x.c, x.d), x.fb);
    }
    sides.erase(std::remove_if(sides.begin(), sides.end(), [](const auto& e) { return e.first == gone; }), sides.end());
    std::sort(added.begin(), added.end());
    const auto middle = static_cast<std::ptrdiff_t>(sides.size());
    sides.insert(sides.end(), added.begin(), added.end());
    std::inplace_merge(sides.begin(), sides.begin() + middle, sides.end(),
                       [](const auto& x, const auto& y) { return x.first < y.first; });
  };
  for (int round = 0; round < max_rounds; ++round) {
    std::fill(touched.begin(), touched.end(), 0);
    made.clear();
    done.clear();
    std::size_t flips = 0;
    for (std::size_t i = 0; i < sides.size();) {
      std::size_t j = i;
      while (j < sides.size() && sides[j].first == sides[i].first) ++j;
      const bool interior = j - i == 2;
      const std::uint64_t key = sides[i].first;
      const int f0 = sides[i].second, f1 = interior ? sides[i + 1].second : -1;
      i = j;
      if (!interior || f0 == f1 || touched[f0] || touched[f1]) continue;
      int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
      int fa = f0, fb = f1;  // fa runs a -> b, fb runs b -> a
      if (!runs(mesh.faces[fa], a, b)) std::swap(fa, fb);
      if (!runs(mesh.faces[fa], a, b) || !runs(mesh.faces[fb], b, a)) continue;  // orientations disagree
      const int c = opposite_corner(mesh.faces[fa], a, b), d = opposite_corner(mesh.faces[fb], a, b);
      if (c < 0 || d < 0 || c == d || !may_lose_a_face(a) || !may_lose_a_face(b)) continue;
      if (!should_flip(mesh.positions[a], mesh.positions[b], mesh.positions[c], mesh.positions[d], cos_bend)) continue;
      if (exists(edge_key(c, d))) continue;  // (a search of the whole table: last, for the few that pass)
      mesh.faces[fa] = {a, d, c};
      mesh.faces[fb] = {d, b, c};
      touched[fa] = touched[fb] = 1;
      --faces_at[a], --faces_at[b], ++faces_at[c], ++faces_at[d];
      made.insert(edge_key(c, d));
      done.push_back({fa, fb, a, b, c, d});
      ++flips;
    }
    if (flips == 0) break;
    report.flips += flips;
    ++report.rounds;
    if (round + 1 < max_rounds) update_sides();
  }
  return report;
}

}  // namespace scanmesh
