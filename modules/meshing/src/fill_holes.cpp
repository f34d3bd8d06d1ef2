// Hole filling: a least-folding triangulation of each loop (dynamic programming in the manner of Barequet
// and Sharir's, with Liepa's weight: the largest dihedral angle first, the area second), then refined
// (long edges split, Delaunay flips) and relaxed so the patch has the loop's edge length and no slivers.
#include "scanmesh/fill_holes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>

#include "scanmesh/flip_edges.h"
#include "scanmesh/geometry.h"

namespace scanmesh {
namespace {

using Edge = std::pair<int, int>;  // (smaller, larger) vertex index

Edge undirected(int a, int b) { return a < b ? Edge{a, b} : Edge{b, a}; }

// Edges of the mesh between vertices that are on some loop, and the third vertex of the face on each
// directed edge (a, b) with a, b on loops.
struct LoopNeighbourhood {
  std::vector<Edge> edges;                          // sorted, unique
  std::vector<std::array<int, 3>> directed;         // (a, b, third), sorted
  std::set<Edge> added;                             // edges between existing vertices that patches made
  bool has_edge(int a, int b) const {
    const Edge e = undirected(a, b);
    return std::binary_search(edges.begin(), edges.end(), e) || added.count(e) > 0;
  }
  int third(int a, int b) const {
    auto it = std::lower_bound(directed.begin(), directed.end(), std::array<int, 3>{a, b, std::numeric_limits<int>::min()});
    return it != directed.end() && (*it)[0] == a && (*it)[1] == b ? (*it)[2] : -1;
  }
};

LoopNeighbourhood loop_neighbourhood(const Mesh& mesh, const std::vector<std::vector<int>>& loops) {
  std::vector<char> on_loop(mesh.num_vertices(), 0);
  for (const auto& loop : loops)
    for (int v : loop) on_loop[v] = 1;
  LoopNeighbourhood n;
  for (const Face& f : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3];
      if (on_loop[a] && on_loop[b]) {
        n.edges.push_back(undirected(a, b));
        n.directed.push_back({a, b, f[(k + 2) % 3]});
      }
    }
  std::sort(n.edges.begin(), n.edges.end());
  n.edges.erase(std::unique(n.edges.begin(), n.edges.end()), n.edges.end());
  std::sort(n.directed.begin(), n.directed.end());
  return n;
}

// A triangulation's weight: its worst fold first (1 - cos of the largest dihedral angle, inside and with
// the faces around the loop), its area second.
struct Cost {
  double fold = std::numeric_limits<double>::infinity();
  double area = std::numeric_limits<double>::infinity();
  bool operator<(const Cost& o) const {
    constexpr double tie = 1e-12;  // folds this close count as equal: the area decides
    if (fold < o.fold - tie) return true;
    if (fold > o.fold + tie) return false;
    return area < o.area;
  }
};

// 1 - cos of the angle between unit normals; a degenerate triangle (zero normal) counts as folded over.
double fold_between(const Vec3& unit_a, const Vec3& unit_b) {
  if (unit_a.squaredNorm() == 0.0 || unit_b.squaredNorm() == 0.0) return unit_a.squaredNorm() == 0.0 ? 2.0 : 0.0;
  return 1.0 - unit_a.dot(unit_b);
}

// Triangulates the ring (local indices 0..n-1, positions p); returns triangles as local index triples,
// empty if none is valid. `outer[k]`: unit normal of the mesh face on the ring's edge k -> k+1 (zero if
// there is none). O(n^3) time, O(n^2) memory.
std::vector<std::array<int, 3>> triangulate_ring(const std::vector<int>& ring, const std::vector<Vec3>& p,
                                                 const std::vector<Vec3>& outer, const LoopNeighbourhood& around) {
  const int n = static_cast<int>(ring.size());
  auto at = [n](int i, int j) { return static_cast<std::size_t>(i) * n + j; };
  // A diagonal i-j is allowed unless it is an edge the mesh (or an earlier patch) already has. The ring
  // passes each vertex once (fill_holes splits it where it does not).
  std::vector<char> allowed(static_cast<std::size_t>(n) * n, 1);
  for (int i = 0; i < n; ++i)
    for (int j = i + 2; j < n; ++j)
      if (!(i == 0 && j == n - 1) && around.has_edge(ring[i], ring[j])) allowed[at(i, j)] = 0;
  std::vector<Cost> cost(static_cast<std::size_t>(n) * n);
  std::vector<int> split(static_cast<std::size_t>(n) * n, -1);
  std::vector<Vec3> unit(static_cast<std::size_t>(n) * n, Vec3::Zero());  // of the triangle on (i, j), inside
  for (int i = 0; i + 1 < n; ++i) {
    cost[at(i, i + 1)] = Cost{0.0, 0.0};
    unit[at(i, i + 1)] = outer[i];  // beyond a ring edge: the mesh face
  }
  for (int len = 2; len < n; ++len)
    for (int i = 0; i + len < n; ++i) {
      const int j = i + len;
      if (!allowed[at(i, j)]) continue;
      Cost best;
      int best_m = -1;
      Vec3 best_unit = Vec3::Zero();
      for (int m = i + 1; m < j; ++m) {
        const Cost& a = cost[at(i, m)];
        const Cost& b = cost[at(m, j)];
        if (!(a.area < std::numeric_limits<double>::infinity()) || !(b.area < std::numeric_limits<double>::infinity())) continue;
        double area = 0.0;
        const Vec3 u = triangle_normal(p[i], p[m], p[j], &area);
        double fold = std::max({a.fold, b.fold, fold_between(u, unit[at(i, m)]), fold_between(u, unit[at(m, j)])});
        if (i == 0 && j == n - 1) fold = std::max(fold, fold_between(u, outer[n - 1]));
        const Cost c{fold, a.area + b.area + area};
        if (c < best) {
          best = c;
          best_m = m;
          best_unit = u;
        }
      }
      cost[at(i, j)] = best;
      split[at(i, j)] = best_m;
      unit[at(i, j)] = best_unit;
    }
  std::vector<std::array<int, 3>> tris;
  if (split[at(0, n - 1)] < 0) return tris;
  std::vector<std::pair<int, int>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j - i < 2) continue;
    const int m = split[at(i, j)];
    tris.push_back({i, m, j});
    stack.emplace_back(i, m);
    stack.emplace_back(m, j);
  }
  return tris;
}

// One loop's patch while it is built: faces over mesh vertex indices (>= 0) and the patch's own new
// vertices (-1, -2, ...: new vertex k is -(k + 1)), each the midpoint of two others when it was made.
struct Patch {
  std::vector<Face> faces;
  std::vector<Vec3> new_positions;
  std::vector<std::pair<int, int>> parents;
};

// Positions of a patch's vertices: the mesh's (read only) and the patch's own.
class PatchPositions {
 public:
  PatchPositions(const Mesh& mesh, const Patch& patch) : mesh_(mesh), patch_(patch) {}
  const Vec3& operator[](int v) const { return v >= 0 ? mesh_.positions[v] : patch_.new_positions[-v - 1]; }

 private:
  const Mesh& mesh_;
  const Patch& patch_;
};

// Edge -> the (one or two) patch faces on it, in face order.
std::map<Edge, std::vector<int>> patch_edges(const Patch& patch) {
  std::map<Edge, std::vector<int>> e;
  for (std::size_t f = 0; f < patch.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) e[undirected(patch.faces[f][k], patch.faces[f][(k + 1) % 3])].push_back(static_cast<int>(f));
  return e;
}

// Of the two faces on edge (a, b), the one running a -> b first.
std::pair<int, int> faces_along(const Patch& patch, int a, int b, const std::vector<int>& fs) {
  const Face& f = patch.faces[fs[0]];
  for (int k = 0; k < 3; ++k)
    if (f[k] == a && f[(k + 1) % 3] == b) return {fs[0], fs[1]};
  return {fs[1], fs[0]};
}

// Splits patch-interior edges longer than 4/3 of `target` at their midpoints (longest first, each face at
// most once per pass), flips edges whose opposite angles sum above pi, and relaxes the new vertices to
// the mean of their neighbours; until no edge is split. Existing vertices never move.
void refine(const Mesh& mesh, Patch& patch, double target, const LoopNeighbourhood& around) {
  constexpr int kPasses = 12;
  const double longest = 4.0 / 3.0 * target;
  const PatchPositions pos(mesh, patch);
  for (int pass = 0; pass < kPasses; ++pass) {
    bool split_any = false;
    {
      auto edges = patch_edges(patch);
      std::vector<std::pair<double, Edge>> longer;
      for (const auto& [e, fs] : edges)
        if (fs.size() == 2) {
          const double l = (pos[e.first] - pos[e.second]).norm();
          if (l > longest) longer.emplace_back(l, e);
        }
      std::sort(longer.begin(), longer.end(), [](const auto& x, const auto& y) { return x.first > y.first || (x.first == y.first && x.second < y.second); });
      std::vector<char> touched(patch.faces.size(), 0);
      for (const auto& [l, e] : longer) {
        const auto& fs = edges[e];
        if (touched[fs[0]] || touched[fs[1]]) continue;
        touched[fs[0]] = touched[fs[1]] = 1;
        const int a = e.first, b = e.second;
        const auto [fa, fb] = faces_along(patch, a, b, fs);  // fa runs a -> b, fb b -> a
        const int c = opposite_corner(patch.faces[fa], a, b), d = opposite_corner(patch.faces[fb], a, b);
        const Vec3 mid = 0.5 * (pos[a] + pos[b]);
        patch.new_positions.push_back(mid);
        patch.parents.emplace_back(a, b);
        const int v = -static_cast<int>(patch.new_positions.size());
        patch.faces[fa] = {a, v, c};
        patch.faces.push_back({v, b, c});
        patch.faces[fb] = {b, v, d};
        patch.faces.push_back({v, a, d});
        split_any = true;
      }
    }
    // Delaunay flips of patch-interior edges, a few rounds.
    for (int round = 0; round < 4; ++round) {
      bool flipped = false;
      auto edges = patch_edges(patch);
      std::vector<char> touched(patch.faces.size(), 0);
      for (const auto& [e, fs] : edges) {
        if (fs.size() != 2 || touched[fs[0]] || touched[fs[1]]) continue;
        const int a = e.first, b = e.second;
        const auto [fa, fb] = faces_along(patch, a, b, fs);
        const int c = opposite_corner(patch.faces[fa], a, b), d = opposite_corner(patch.faces[fb], a, b);
        if (c == d || edges.count(undirected(c, d)) || (c >= 0 && d >= 0 && around.has_edge(c, d))) continue;
        if (!should_flip(pos[a], pos[b], pos[c], pos[d], -1.0)) continue;  // a fresh patch: any bend
        patch.faces[fa] = {a, d, c};
        patch.faces[fb] = {d, b, c};
        touched[fa] = touched[fb] = 1;
        edges[undirected(c, d)];  // taken: no later flip of this round makes it again
        flipped = true;
      }
      if (!flipped) break;
    }
    // Relax the patch's own vertices towards the mean of their neighbours (a membrane over the loop).
    const std::size_t n_new = patch.new_positions.size();
    if (n_new > 0) {
      std::vector<std::vector<int>> nbr(n_new);
      for (const Face& f : patch.faces)
        for (int k = 0; k < 3; ++k) {
          const int v = f[k], w = f[(k + 1) % 3];
          if (v < 0) nbr[-v - 1].push_back(w);
          if (w < 0) nbr[-w - 1].push_back(v);
        }
      for (int it = 0; it < 10; ++it)
        for (std::size_t k = 0; k < n_new; ++k) {
          if (nbr[k].empty()) continue;
          Vec3 s = Vec3::Zero();
          for (int w : nbr[k]) s += pos[w];
          patch.new_positions[k] = s / static_cast<double>(nbr[k].size());
        }
    }
    if (!split_any) break;
  }
}

// Triangulates and refines one loop into `patch`; false only for fewer than three vertices.
bool make_patch(const Mesh& mesh, const std::vector<int>& ring, const LoopNeighbourhood& around, Patch& patch) {
  patch = Patch{};
  const std::size_t n = ring.size();
  if (n < 3) return false;
  std::vector<Vec3> p(n), outer(n);
  double perimeter = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const int a = ring[k], b = ring[(k + 1) % n];
    p[k] = mesh.positions[a];
    perimeter += (mesh.positions[b] - mesh.positions[a]).norm();
    const int c = around.third(b, a);  // the mesh face on this edge runs b -> a
    outer[k] = c >= 0 ? triangle_normal(mesh.positions[b], mesh.positions[a], mesh.positions[c]) : Vec3(Vec3::Zero());
  }
  const auto tris = triangulate_ring(ring, p, outer, around);
  if (!tris.empty()) {
    for (const auto& t : tris) patch.faces.push_back({ring[t[0]], ring[t[1]], ring[t[2]]});
  } else {
    // Every triangulation needs a diagonal the mesh already has (the loop's vertices are joined around
    // the other side): a fan around a new vertex at the loop's centroid needs none.
    Vec3 centre = Vec3::Zero();
    for (const Vec3& q : p) centre += q;
    patch.new_positions.push_back(centre / static_cast<double>(n));
    patch.parents.emplace_back(ring[0], ring[n / 2]);  // its properties: the mean of two opposite loop vertices
    for (std::size_t k = 0; k < n; ++k) patch.faces.push_back({ring[k], ring[(k + 1) % n], -1});
  }
  refine(mesh, patch, perimeter / static_cast<double>(n), around);
  return true;
}

// Splits a ring at every vertex it passes twice into rings that pass each vertex once (appended to `out`);
// parts of fewer than three vertices (a slit: out along an edge and back) are dropped.
void split_at_repeats(const std::vector<int>& ring, std::vector<std::vector<int>>& out) {
  std::vector<std::vector<int>> todo{ring};
  while (!todo.empty()) {
    std::vector<int> r = std::move(todo.back());
    todo.pop_back();
    std::map<int, std::size_t> seen;
    bool split = false;
    for (std::size_t k = 0; k < r.size() && !split; ++k) {
      auto [it, fresh] = seen.emplace(r[k], k);
      if (fresh) continue;
      const std::size_t i = it->second;
      std::vector<int> inner(r.begin() + static_cast<long>(i), r.begin() + static_cast<long>(k));
      std::vector<int> rest(r.begin(), r.begin() + static_cast<long>(i));
      rest.insert(rest.end(), r.begin() + static_cast<long>(k), r.end());
      todo.push_back(std::move(rest));  // LIFO: inner first, then the rest, in ring order
      todo.push_back(std::move(inner));
      split = true;
    }
    if (!split && r.size() >= 3) out.push_back(std::move(r));
  }
}

// The patch's edges between existing vertices that are not edges of its ring.
std::vector<Edge> diagonals(const Patch& patch, const std::vector<int>& ring) {
  std::set<Edge> on_ring;
  for (std::size_t k = 0; k < ring.size(); ++k) on_ring.insert(undirected(ring[k], ring[(k + 1) % ring.size()]));
  std::vector<Edge> out;
  for (const Face& f : patch.faces)
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3];
      if (a >= 0 && b >= 0 && !on_ring.count(undirected(a, b))) out.push_back(undirected(a, b));
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

std::vector<FilledHole> fill_holes(Mesh& mesh, const std::vector<std::vector<int>>& loops) {
  std::vector<FilledHole> out(loops.size());
  LoopNeighbourhood around = loop_neighbourhood(mesh, loops);
  // A loop that passes a vertex twice (two holes touching there) is closed as its simple parts: filled
  // whole, one vertex pair could become a diagonal twice, from its two passes.
  std::vector<std::vector<int>> rings;
  std::vector<std::size_t> ring_loop;
  for (std::size_t l = 0; l < loops.size(); ++l) {
    if (loops[l].size() > kMaxFillLoopVertices) continue;
    split_at_repeats(loops[l], rings);
    ring_loop.resize(rings.size(), l);
  }
  std::vector<Patch> patches(rings.size());
  std::vector<char> made(rings.size(), 0);
  // The triangulation costs a ring's length cubed: rings are taken shortest first while the sum stays
  // within a budget proportional to the mesh (and at least a few seconds' worth), so that a mesh made of
  // long loops still costs time linear in its size.
  std::vector<char> attempt(rings.size(), 0);
  {
    std::vector<std::size_t> order(rings.size());
    for (std::size_t r = 0; r < rings.size(); ++r) order[r] = r;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return rings[a].size() < rings[b].size(); });
    const double budget = 1e9 + 600.0 * static_cast<double>(mesh.num_faces());
    double spent = 0.0;
    for (std::size_t r : order) {
      const auto n = static_cast<double>(rings[r].size());
      if (spent + n * n * n > budget) break;
      spent += n * n * n;
      attempt[r] = 1;
    }
  }
  const auto count = static_cast<long>(rings.size());
  // Each ring on its own (the mesh is only read)...
#pragma omp parallel for schedule(dynamic, 1)
  for (long r = 0; r < count; ++r) made[r] = attempt[r] && make_patch(mesh, rings[r], around, patches[r]) ? 1 : 0;
  // ... then, in order, a patch that would repeat a diagonal of an earlier one (two holes sharing two
  // vertices) is made again with those edges taken. The same mesh whatever the thread count.
  for (std::size_t r = 0; r < rings.size(); ++r) {
    if (!made[r]) continue;
    std::vector<Edge> mine = diagonals(patches[r], rings[r]);
    const bool clash = std::any_of(mine.begin(), mine.end(), [&](const Edge& e) { return around.added.count(e) > 0; });
    if (clash) {
      made[r] = make_patch(mesh, rings[r], around, patches[r]) ? 1 : 0;
      if (!made[r]) continue;
      mine = diagonals(patches[r], rings[r]);
    }
    around.added.insert(mine.begin(), mine.end());
  }
  // Appended loop by loop (a loop's rings are consecutive), so each loop's patch is one range.
  for (std::size_t r = 0; r < rings.size(); ++r) {
    if (!made[r]) continue;
    FilledHole& h = out[ring_loop[r]];
    if (!h.filled) {
      h.filled = true;
      h.first_vertex = mesh.num_vertices();
      h.first_face = mesh.num_faces();
    }
    const Patch& patch = patches[r];
    const auto base = static_cast<int>(mesh.num_vertices());
    auto global = [&](int v) { return v >= 0 ? v : base + (-v - 1); };
    for (std::size_t k = 0; k < patch.new_positions.size(); ++k) {
      mesh.positions.push_back(patch.new_positions[k]);
      const int a = global(patch.parents[k].first), b = global(patch.parents[k].second);
      for (auto& prop : mesh.vertex_properties) prop.values.push_back(0.5 * (prop.values[a] + prop.values[b]));
    }
    for (Face f : patch.faces) {
      for (int& v : f) v = global(v);
      mesh.faces.push_back(f);
    }
    h.vertices = mesh.num_vertices() - h.first_vertex;
    h.faces = mesh.num_faces() - h.first_face;
  }
  return out;
}

std::vector<std::vector<int>> zip_slits(Mesh& mesh, const std::vector<std::vector<int>>& loops, std::size_t* zipped) {
  if (zipped != nullptr) *zipped = 0;
  // The faces at each loop vertex (a loop vertex's slot in `at`), kept up to date as welds move faces.
  std::vector<int> slot(mesh.num_vertices(), -1);
  int slots = 0;
  for (const auto& loop : loops)
    for (int v : loop)
      if (slot[v] < 0) slot[v] = slots++;
  std::vector<std::vector<int>> at(static_cast<std::size_t>(slots));
  for (std::size_t f = 0; f < mesh.num_faces(); ++f)
    for (int v : mesh.faces[f])
      if (slot[v] >= 0) at[slot[v]].push_back(static_cast<int>(f));
  // Whether welding w into v keeps every edge at v to at most two faces and every face's corners apart.
  std::vector<int> spokes;
  auto can_weld = [&](int v, int w) {
    spokes.clear();
    for (int s : {v, w})
      for (int f : at[slot[s]])
        for (int x : mesh.faces[f]) {
          if (x == (s == v ? w : v)) return false;
          if (x != s) spokes.push_back(x);
        }
    std::sort(spokes.begin(), spokes.end());
    for (std::size_t k = 2; k < spokes.size(); ++k)
      if (spokes[k] == spokes[k - 2]) return false;
    return true;
  };
  std::vector<std::vector<int>> out;
  for (const auto& loop : loops) {
    std::vector<int> ring = loop;
    bool welded = false;
    for (std::size_t i = 0; ring.size() >= 3 && i < ring.size();) {
      const std::size_t n = ring.size();
      const int v = ring[(i + n - 1) % n], w = ring[(i + 1) % n];
      if (v == w || mesh.positions[v] != mesh.positions[w] || !can_weld(v, w)) {
        ++i;
        continue;
      }
      for (int f : at[slot[w]]) {
        for (int& x : mesh.faces[f])
          if (x == w) x = v;
        at[slot[v]].push_back(f);
      }
      at[slot[w]].clear();
      // a and w leave the ring (a's two edges are one now, between two faces); look again before v.
      const std::size_t first = std::min(i, (i + 1) % n), second = std::max(i, (i + 1) % n);
      ring.erase(ring.begin() + static_cast<long>(second));
      ring.erase(ring.begin() + static_cast<long>(first));
      welded = true;
      i = i >= 2 ? i - 2 : 0;
    }
    if (ring.size() >= 3) out.push_back(std::move(ring));
    else if (welded && zipped != nullptr) ++*zipped;
  }
  return out;
}

void remove_patches(Mesh& mesh, std::vector<FilledHole>& patches, const std::vector<char>& keep) {
  std::vector<char> drop_face(mesh.num_faces(), 0), drop_vertex(mesh.num_vertices(), 0);
  for (std::size_t i = 0; i < patches.size(); ++i) {
    if (!patches[i].filled || keep[i]) continue;
    std::fill_n(drop_face.begin() + static_cast<long>(patches[i].first_face), patches[i].faces, 1);
    std::fill_n(drop_vertex.begin() + static_cast<long>(patches[i].first_vertex), patches[i].vertices, 1);
  }
  std::vector<int> remap(mesh.num_vertices(), -1);
  std::size_t nv = 0;
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v)
    if (!drop_vertex[v]) {
      remap[v] = static_cast<int>(nv);
      mesh.positions[nv] = mesh.positions[v];
      for (auto& prop : mesh.vertex_properties) prop.values[nv] = prop.values[v];
      ++nv;
    }
  mesh.positions.resize(nv);
  for (auto& prop : mesh.vertex_properties) prop.values.resize(nv);
  std::size_t nf = 0;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f)
    if (!drop_face[f]) {
      Face g = mesh.faces[f];
      for (int& v : g) v = remap[v];
      mesh.faces[nf++] = g;
    }
  mesh.faces.resize(nf);
  // The kept patches' ranges after the removal.
  std::size_t face_shift = 0, vertex_shift = 0;
  for (std::size_t i = 0; i < patches.size(); ++i) {
    FilledHole& h = patches[i];
    if (!h.filled) continue;
    if (!keep[i]) {
      face_shift += h.faces;
      vertex_shift += h.vertices;
      h = FilledHole{};
      continue;
    }
    h.first_face -= face_shift;
    h.first_vertex -= vertex_shift;
  }
}

}  // namespace scanmesh
