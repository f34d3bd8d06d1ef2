#include "scanmesh/topology.h"

#include <algorithm>
#include <numeric>

namespace scanmesh {
namespace {

// Fills a CSR adjacency from (row, value) pairs; values within a row keep their order of appearance.
Adjacency build_csr(std::size_t rows, const std::vector<std::pair<int, int>>& pairs) {
  Adjacency a;
  a.offsets.assign(rows + 1, 0);
  for (const auto& [r, v] : pairs) ++a.offsets[r + 1];
  std::partial_sum(a.offsets.begin(), a.offsets.end(), a.offsets.begin());
  a.indices.resize(pairs.size());
  std::vector<int> fill(a.offsets.begin(), a.offsets.end() - 1);
  for (const auto& [r, v] : pairs) a.indices[fill[r]++] = v;
  return a;
}

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

Topology build_topology(const Mesh& mesh, bool with_face_faces) {
  Topology t;
  const std::size_t nv = mesh.num_vertices();
  const std::size_t nf = mesh.num_faces();

  {  // vertex -> faces: faces are visited in ascending order, so rows come out sorted.
    std::vector<std::pair<int, int>> pairs;
    pairs.reserve(3 * nf);
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const int v = mesh.faces[f][k];
        // A degenerate face may name a vertex twice; list it once.
        if (k > 0 && mesh.faces[f][k - 1] == v) continue;
        if (k == 2 && mesh.faces[f][0] == v) continue;
        pairs.emplace_back(v, static_cast<int>(f));
      }
    t.vertex_faces = build_csr(nv, pairs);
  }

  // Half-edges keyed by their undirected edge; sorting gives unique edges in a deterministic order.
  struct HalfEdge {
    int a, b, face, local;
  };
  // Counting sort by the smaller vertex (linear), then each vertex's few half-edges by the rest of the key.
  std::vector<HalfEdge> half(3 * nf);
  {
    std::vector<int> start(nv + 1, 0);
    for (const Face& f : mesh.faces)
      for (int k = 0; k < 3; ++k) ++start[std::min(f[k], f[(k + 1) % 3]) + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (std::size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const int u = mesh.faces[f][k];
        const int w = mesh.faces[f][(k + 1) % 3];
        half[fill[std::min(u, w)]++] = {std::min(u, w), std::max(u, w), static_cast<int>(f), k};
      }
    for (std::size_t v = 0; v < nv; ++v)
      if (start[v + 1] - start[v] > 1)
        std::sort(half.begin() + start[v], half.begin() + start[v + 1], [](const HalfEdge& x, const HalfEdge& y) {
          return std::tie(x.b, x.face, x.local) < std::tie(y.b, y.face, y.local);
        });
  }

  t.face_edges.assign(nf, {-1, -1, -1});
  // The tables below at their final size from the start: grown by push_back they were copied and
  // freshly faulted in several times (half of build_topology's time on a million faces).
  std::size_t unique_edges = half.empty() ? 0 : 1;
  for (std::size_t i = 1; i < half.size(); ++i) unique_edges += half[i].a != half[i - 1].a || half[i].b != half[i - 1].b ? 1 : 0;
  t.edges.reserve(unique_edges);
  t.edge_faces.offsets.reserve(unique_edges + 1);
  t.edge_faces.indices.reserve(half.size());
  t.edge_faces.offsets.assign(1, 0);
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i;
    const int e = static_cast<int>(t.edges.size());
    t.edges.push_back({half[i].a, half[i].b});
    int last_face = -1;
    for (; j < half.size() && half[j].a == half[i].a && half[j].b == half[i].b; ++j) {
      t.face_edges[half[j].face][half[j].local] = e;
      if (half[j].face != last_face) t.edge_faces.indices.push_back(half[j].face);
      last_face = half[j].face;
    }
    t.edge_faces.offsets.push_back(static_cast<int>(t.edge_faces.indices.size()));
    i = j;
  }
  // 48 bytes per face, no longer needed: freed before the adjacency lists below are built (it was half of
  // the denoiser's peak memory).
  std::vector<HalfEdge>().swap(half);

  {  // vertex -> vertices from the unique edges (self-loops of degenerate faces are skipped).
    std::vector<std::pair<int, int>> pairs;
    pairs.reserve(2 * t.edges.size());
    for (const auto& [a, b] : t.edges) {
      if (a == b) continue;
      pairs.emplace_back(a, b);
      pairs.emplace_back(b, a);
    }
    t.vertex_vertices = build_csr(nv, pairs);
    sort_unique_rows(t.vertex_vertices);
  }

  // face -> edge-adjacent faces. Across a non-manifold edge (k > 2 faces) each face is linked to the
  // faces before and after it on that edge only, so a fan of k faces costs O(k) links, not O(k^2), and
  // stays connected.
  if (with_face_faces) {
    std::vector<std::pair<int, int>> pairs;
    pairs.reserve(2 * t.edge_faces.indices.size());
    for (std::size_t e = 0; e < t.edges.size(); ++e) {
      const int* f = t.edge_faces.begin(e);
      const int k = t.edge_faces.size(e);
      for (int a = 0; a + 1 < k; ++a) {
        pairs.emplace_back(f[a], f[a + 1]);
        pairs.emplace_back(f[a + 1], f[a]);
      }
    }
    t.face_faces = build_csr(nf, pairs);
    sort_unique_rows(t.face_faces);
  }

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

}  // namespace scanmesh
