#include "scanmesh/topology.h"

#include <algorithm>
#include <numeric>
#include <tuple>

namespace scanmesh {
namespace {

// Sorts each row and drops repeats, in place: no second table and no allocation per row (a million rows
// of small vectors left the heap fragmented for the rest of a run).
void sort_unique_rows(Adjacency& a) {
  int kept = 0;
  for (std::size_t i = 0; i < a.rows(); ++i) {
    int* first = a.indices.data() + a.offsets[i];
    int* last = a.indices.data() + a.offsets[i + 1];
    std::sort(first, last);
    last = std::unique(first, last);
    a.offsets[i] = kept;  // row i's old start is no longer needed: rows are read front to back
    for (const int* p = first; p != last; ++p) a.indices[static_cast<std::size_t>(kept++)] = *p;  // moves down or stays
  }
  a.offsets.back() = kept;
  a.indices.resize(static_cast<std::size_t>(kept));
}

}  // namespace

std::size_t Topology::num_boundary_edges() const {
  std::size_t n = 0;
  for (std::size_t e = 0; e < edges.size(); ++e) n += is_boundary_edge(e) ? 1 : 0;
  return n;
}

std::size_t Topology::num_nonmanifold_edges() const {
  std::size_t n = 0;
  for (std::size_t e = 0; e < edges.size(); ++e) n += is_nonmanifold_edge(e) ? 1 : 0;
  return n;
}

void add_vertex_vertices(Topology& t) {
  // Row v gets the smaller ends c of edges (c, v) in ascending order, then the larger ends of edges (v, b)
  // in ascending order: sorted and without repeats as filled. Self-loops of degenerate faces are skipped.
  auto& a = t.vertex_vertices;
  a.offsets.assign(t.vertex_faces.rows() + 1, 0);
  a.indices.clear();
  for (const auto& [p, q] : t.edges)
    if (p != q) ++a.offsets[p + 1], ++a.offsets[q + 1];
  std::partial_sum(a.offsets.begin(), a.offsets.end(), a.offsets.begin());
  a.indices.resize(static_cast<std::size_t>(a.offsets.back()));
  std::vector<int> fill(a.offsets.begin(), a.offsets.end() - 1);
  for (const auto& [p, q] : t.edges)
    if (p != q) {
      a.indices[static_cast<std::size_t>(fill[p]++)] = q;
      a.indices[static_cast<std::size_t>(fill[q]++)] = p;
    }
}

void add_face_faces(Topology& t, std::size_t num_faces) {
  // Across a non-manifold edge (k > 2 faces) each face is linked to the faces before and after it on that
  // edge only, so a fan of k faces costs O(k) links, not O(k^2), and stays connected.
  auto& a = t.face_faces;
  const std::size_t ne = t.edges.size();
  a.offsets.assign(num_faces + 1, 0);
  a.indices.clear();
  for (std::size_t e = 0; e < ne; ++e) {
    const int* f = t.edge_faces.begin(e);
    for (int k = 0; k + 1 < t.edge_faces.size(e); ++k) ++a.offsets[f[k] + 1], ++a.offsets[f[k + 1] + 1];
  }
  std::partial_sum(a.offsets.begin(), a.offsets.end(), a.offsets.begin());
  a.indices.resize(static_cast<std::size_t>(a.offsets.back()));
  std::vector<int> fill(a.offsets.begin(), a.offsets.end() - 1);
  for (std::size_t e = 0; e < ne; ++e) {
    const int* f = t.edge_faces.begin(e);
    for (int k = 0; k + 1 < t.edge_faces.size(e); ++k) {
      a.indices[static_cast<std::size_t>(fill[f[k]]++)] = f[k + 1];
      a.indices[static_cast<std::size_t>(fill[f[k + 1]]++)] = f[k];
    }
  }
  sort_unique_rows(a);  // two faces sharing two edges (degenerate input) are listed once
}

Topology build_topology(const Mesh& mesh, bool with_face_faces) {
  Topology t;
  const std::size_t nv = mesh.num_vertices();
  const std::size_t nf = mesh.num_faces();
  const auto nvl = static_cast<long>(nv);

  // Every table below is counted first and then filled in place: no temporary (row, value) pair lists and
  // no tables grown by push_back (fresh memory has to be cleared by the kernel page by page, and on a
  // million faces that clearing was a third of the build).
  {  // vertex -> faces: faces are visited in ascending order, so rows come out sorted.
    auto& a = t.vertex_faces;
    // A degenerate face may name a vertex twice; it is listed once.
    auto repeats = [&](const Face& f, int k) { return (k > 0 && f[k - 1] == f[k]) || (k == 2 && f[0] == f[2]); };
    a.offsets.assign(nv + 1, 0);
    for (const Face& f : mesh.faces)
      for (int k = 0; k < 3; ++k)
        if (!repeats(f, k)) ++a.offsets[f[k] + 1];
    std::partial_sum(a.offsets.begin(), a.offsets.end(), a.offsets.begin());
    a.indices.resize(static_cast<std::size_t>(a.offsets.back()));
    std::vector<int> fill(a.offsets.begin(), a.offsets.end() - 1);
    for (std::size_t fi = 0; fi < nf; ++fi)
      for (int k = 0; k < 3; ++k)
        if (!repeats(mesh.faces[fi], k)) a.indices[static_cast<std::size_t>(fill[mesh.faces[fi][k]]++)] = static_cast<int>(fi);
  }

  // Edges, in (smaller, larger) order, found from each vertex's faces: vertex v owns the half-edges whose
  // smaller end is v, sorted by (larger end, face, corner); runs of equal larger ends are its edges, in
  // order. Two passes over the vertices in parallel (count, then fill at the counted offsets), so the
  // result does not depend on the thread count.
  struct HalfEdge {
    int b, face, local;
    bool operator<(const HalfEdge& o) const { return std::tie(b, face, local) < std::tie(o.b, o.face, o.local); }
  };
  auto owned = [&](std::size_t v, std::vector<HalfEdge>& out) {
    out.clear();
    for (const int* f = t.vertex_faces.begin(v); f != t.vertex_faces.end(v); ++f)
      for (int k = 0; k < 3; ++k) {
        const int u = mesh.faces[*f][k];
        const int w = mesh.faces[*f][(k + 1) % 3];
        if (std::min(u, w) == static_cast<int>(v)) out.push_back({std::max(u, w), *f, k});
      }
    std::sort(out.begin(), out.end());
  };
  std::vector<int> edge_start(nv + 1, 0), entry_start(nv + 1, 0);  // per vertex: its first edge, first edge-face entry
#pragma omp parallel
  {
    std::vector<HalfEdge> half;
#pragma omp for schedule(dynamic, 2048)
    for (long v = 0; v < nvl; ++v) {
      owned(static_cast<std::size_t>(v), half);
      int edges = 0, entries = 0;
      for (std::size_t i = 0; i < half.size(); ++i) {
        const bool new_edge = i == 0 || half[i].b != half[i - 1].b;
        edges += new_edge ? 1 : 0;
        entries += new_edge || half[i].face != half[i - 1].face ? 1 : 0;
      }
      edge_start[v + 1] = edges;
      entry_start[v + 1] = entries;
    }
  }
  std::partial_sum(edge_start.begin(), edge_start.end(), edge_start.begin());
  std::partial_sum(entry_start.begin(), entry_start.end(), entry_start.begin());
  const auto ne = static_cast<std::size_t>(edge_start.back());
  t.edges.resize(ne);
  t.edge_faces.offsets.resize(ne + 1);
  t.edge_faces.offsets[ne] = entry_start.back();
  t.edge_faces.indices.resize(static_cast<std::size_t>(entry_start.back()));
  t.face_edges.assign(nf, {-1, -1, -1});
#pragma omp parallel
  {
    std::vector<HalfEdge> half;
#pragma omp for schedule(dynamic, 2048)
    for (long v = 0; v < nvl; ++v) {
      owned(static_cast<std::size_t>(v), half);
      int e = edge_start[v] - 1, entry = entry_start[v];
      for (std::size_t i = 0; i < half.size(); ++i) {
        const bool new_edge = i == 0 || half[i].b != half[i - 1].b;
        if (new_edge) {
          ++e;
          t.edges[static_cast<std::size_t>(e)] = {static_cast<int>(v), half[i].b};
          t.edge_faces.offsets[static_cast<std::size_t>(e)] = entry;
        }
        if (new_edge || half[i].face != half[i - 1].face) t.edge_faces.indices[static_cast<std::size_t>(entry++)] = half[i].face;
        t.face_edges[half[i].face][half[i].local] = e;  // each (face, corner) belongs to one vertex's list
      }
    }
  }
  std::vector<int>().swap(edge_start);
  std::vector<int>().swap(entry_start);

  add_vertex_vertices(t);
  if (with_face_faces) add_face_faces(t, nf);

  t.boundary_vertex.assign(nv, 0);
  // Boundary successor following face orientation: boundary half-edge u->w of its only face.
  std::vector<int> next(nv, -1), boundary_degree(nv, 0);
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    if (!t.is_boundary_edge(e) || t.edges[e][0] == t.edges[e][1]) continue;
    const int f = t.edge_faces.indices[t.edge_faces.offsets[e]];
    for (int k = 0; k < 3; ++k)
      if (t.face_edges[f][k] == static_cast<int>(e)) {
        const int u = mesh.faces[f][k];
        const int w = mesh.faces[f][(k + 1) % 3];
        t.boundary_vertex[u] = t.boundary_vertex[w] = 1;
        ++boundary_degree[u];
        ++boundary_degree[w];
        next[u] = w;
        break;
      }
  }
  // Chain vertices of boundary degree 2 into loops; start chains at irregular vertices first.
  std::vector<std::uint8_t> used(nv, 0);
  auto walk = [&](int start) {
    std::vector<int> loop;
    int v = start;
    while (v >= 0 && !used[v]) {
      used[v] = 1;
      loop.push_back(v);
      if (boundary_degree[v] != 2 && v != start) break;
      v = next[v];
    }
    if (loop.size() >= 2) {
      const bool closed = loop.size() >= 3 && next[loop.back()] == loop.front() &&
                          boundary_degree[loop.front()] == 2 && boundary_degree[loop.back()] == 2;
      t.boundary_loops.push_back(std::move(loop));
      t.boundary_loop_closed.push_back(closed ? 1 : 0);
    }
  };
  for (std::size_t v = 0; v < nv; ++v)
    if (boundary_degree[v] != 0 && boundary_degree[v] != 2) walk(static_cast<int>(v));
  for (std::size_t v = 0; v < nv; ++v)
    if (boundary_degree[v] == 2 && !used[v]) walk(static_cast<int>(v));
  return t;
}

std::size_t count_components(const Mesh& mesh, const Topology& topology) {
  const std::size_t nv = mesh.num_vertices();
  std::vector<int> label(nv, -1);
  std::vector<int> stack;
  std::size_t components = 0;
  for (std::size_t s = 0; s < nv; ++s) {
    if (label[s] >= 0 || topology.vertex_faces.size(s) == 0) continue;
    stack.push_back(static_cast<int>(s));
    label[s] = static_cast<int>(components);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (const int* w = topology.vertex_vertices.begin(v); w != topology.vertex_vertices.end(v); ++w)
        if (label[*w] < 0) {
          label[*w] = static_cast<int>(components);
          stack.push_back(*w);
        }
    }
    ++components;
  }
  return components;
}

std::vector<int> vertex_pieces(const Mesh& mesh) {
  std::vector<int> parent(mesh.num_vertices());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  // Linking the larger root under the smaller keeps every root the smallest index of its piece.
  for (const Face& f : mesh.faces)
    for (int k = 1; k < 3; ++k) {
      const int a = find(f[0]), b = find(f[k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  for (std::size_t v = 0; v < parent.size(); ++v) parent[v] = find(static_cast<int>(v));
  return parent;
}

}  // namespace scanmesh
