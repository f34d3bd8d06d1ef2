#include "scanmesh/vertex_update.h"

#include <cmath>

#include "scanmesh/normal_filtering.h"

namespace scanmesh {

BoundaryCurves build_boundary_curves(const Mesh& mesh, const Topology& topology) {
  BoundaryCurves c;
  const std::size_t nv = mesh.num_vertices();
  c.prev.assign(nv, -1);
  c.next.assign(nv, -1);
  c.vertex_edges.assign(nv, {-1, -1});
  c.loop_edges.offsets.assign(1, 0);
  // The face owning boundary edge a->b: the only face on that edge.
  auto owning_face = [&](int a, int b) {
    for (const int* f = topology.vertex_faces.begin(a); f != topology.vertex_faces.end(a); ++f)
      for (int k = 0; k < 3; ++k)
        if (mesh.faces[*f][k] == a && mesh.faces[*f][(k + 1) % 3] == b &&
            topology.is_boundary_edge(static_cast<std::size_t>(topology.face_edges[*f][k])))
          return *f;
    return -1;
  };
  for (std::size_t l = 0; l < topology.boundary_loops.size(); ++l) {
    const auto& loop = topology.boundary_loops[l];
    const bool closed = topology.boundary_loop_closed[l] != 0;
    const std::size_t n = loop.size();
    const std::size_t edge_count = closed ? n : n - 1;
    for (std::size_t k = 0; k < edge_count; ++k) {
      const int a = loop[k], b = loop[(k + 1) % n];
      const int f = owning_face(a, b);
      if (f < 0) continue;
      const int e = static_cast<int>(c.edges.size());
      c.edges.push_back({a, b, f});
      c.loop_edges.indices.push_back(e);
      auto attach = [&](int v, int edge) {
        auto& slots = c.vertex_edges[v];
        if (slots[0] < 0) slots[0] = edge;
        else if (slots[1] < 0) slots[1] = edge;
      };
      attach(a, e);
      attach(b, e);
    }
    c.loop_edges.offsets.push_back(static_cast<int>(c.loop_edges.indices.size()));
    c.loop_closed.push_back(closed ? 1 : 0);
    for (std::size_t k = 0; k < n; ++k) {
      const bool has_prev = closed || k > 0;
      const bool has_next = closed || k + 1 < n;
      if (has_prev && has_next) {
        c.prev[loop[k]] = loop[(k + n - 1) % n];
        c.next[loop[k]] = loop[(k + 1) % n];
      }
    }
  }
  return c;
}

void filter_boundary_normals(const std::vector<Vec3>& positions, const BoundaryCurves& curves,
                             const std::vector<Vec3>& filtered_face_normals, double sigma_s,
                             RobustEstimator estimator, double radius_factor, std::vector<Vec3>& filtered) {
  const std::size_t ne = curves.edges.size();
  std::vector<Vec3> m(ne), mid(ne);
  std::vector<double> len(ne);
  double mean_len = 0.0;
  for (std::size_t e = 0; e < ne; ++e) {
    const auto& edge = curves.edges[e];
    const Vec3 d = positions[edge.b] - positions[edge.a];
    len[e] = d.norm();
    mean_len += len[e];
    mid[e] = 0.5 * (positions[edge.a] + positions[edge.b]);
    const Vec3 out = d.cross(filtered_face_normals[edge.face]);
    const double l = out.norm();
    m[e] = l > 0.0 ? Vec3(out / l) : Vec3::Zero();
  }
  filtered.assign(ne, Vec3::Zero());
  if (ne == 0) return;
  mean_len /= static_cast<double>(ne);
  const double sigma_c = mean_len;
  const double radius = radius_factor * mean_len;
  const auto loops = static_cast<long>(curves.loop_edges.rows());
#pragma omp parallel for schedule(dynamic, 1)
  for (long l = 0; l < loops; ++l) {
    const int* edges = curves.loop_edges.begin(l);
    const int n = curves.loop_edges.size(l);
    const bool closed = curves.loop_closed[l] != 0;
    for (int k = 0; k < n; ++k) {
      const int i = edges[k];
      Vec3 sum = Vec3::Zero();
      auto add = [&](int j) {
        const double x = (m[i] - m[j]).norm();
        const double d = (mid[i] - mid[j]).norm();
        sum += len[j] * std::exp(-d * d / (2.0 * sigma_c * sigma_c)) * robust_weight(estimator, x, sigma_s) * m[j];
        return d <= radius;
      };
      add(i);
      // Walk both ways along the loop while within the radius (at most half the loop each way).
      for (int step = 1; step <= n / 2; ++step) {
        int kk = k + step;
        if (kk >= n) {
          if (!closed) break;
          kk -= n;
        }
        if ((mid[edges[kk]] - mid[i]).norm() > radius || !add(edges[kk])) break;
      }
      for (int step = 1; step <= (n - 1) / 2; ++step) {
        int kk = k - step;
        if (kk < 0) {
          if (!closed) break;
          kk += n;
        }
        if ((mid[edges[kk]] - mid[i]).norm() > radius || !add(edges[kk])) break;
      }
      const double l2 = sum.norm();
      filtered[i] = l2 > 0.0 ? Vec3(sum / l2) : m[i];
    }
  }
}

void update_vertices(const std::vector<Vec3>& positions, const Topology& topology, const FaceGeometry& geometry,
                     const std::vector<Vec3>& filtered_normals, double lambda, const BoundaryCurves* boundary,
                     const std::vector<Vec3>* boundary_normals, std::vector<Vec3>& updated) {
  const auto nv = static_cast<long>(positions.size());
  updated.resize(positions.size());
#pragma omp parallel for schedule(static)
  for (long i = 0; i < nv; ++i) {
    const Vec3& vi = positions[i];
    const int nfaces = topology.vertex_faces.size(i);
    if (nfaces == 0) {  // isolated vertex: nothing to fit
      updated[i] = vi;
      continue;
    }
    // Edge-normal orthogonality: move towards the planes of the filtered normals through the centroids.
    Vec3 fit = Vec3::Zero();
    Vec3 vertex_normal = Vec3::Zero();
    for (const int* f = topology.vertex_faces.begin(i); f != topology.vertex_faces.end(i); ++f) {
      const Vec3& n = filtered_normals[*f];
      fit += n * n.dot(geometry.centroids[*f] - vi);
      vertex_normal += geometry.areas[*f] * n;
    }
    fit /= static_cast<double>(nfaces);
    const double nlen = vertex_normal.norm();
    if (nlen > 0.0) vertex_normal /= nlen;

    Vec3 r = Vec3::Zero();
    const bool on_boundary = boundary != nullptr && topology.boundary_vertex[i] != 0;
    if (!on_boundary) {
      // D_i with w_ij = |v_i - v_j|^2, then R_i = D_i + tangential part of D_i.
      Vec3 wsum = Vec3::Zero();
      double w = 0.0;
      for (const int* j = topology.vertex_vertices.begin(i); j != topology.vertex_vertices.end(i); ++j) {
        const double wij = (positions[*j] - vi).squaredNorm();
        wsum += wij * positions[*j];
        w += wij;
      }
      if (w > 0.0) {
        const Vec3 d = wsum / w - vi;
        r = d + (d - d.dot(vertex_normal) * vertex_normal);
      }
    } else {
      // Boundary vertex: fit the filtered boundary normals of its boundary edges (removes noise across
      // the boundary curve without pulling it inwards) ...
      const auto& slots = boundary->vertex_edges[i];
      int count = 0;
      Vec3 bfit = Vec3::Zero();
      for (int e : slots) {
        if (e < 0) continue;
        const auto& edge = boundary->edges[e];
        const Vec3& m = (*boundary_normals)[e];
        bfit += m * m.dot(0.5 * (positions[edge.a] + positions[edge.b]) - vi);
        ++count;
      }
      if (count > 0) fit += bfit / static_cast<double>(count);
      // ... and even out edge lengths along the boundary only (twice, like the tangential part inside).
      const int p = boundary->prev[i], q = boundary->next[i];
      if (p >= 0 && q >= 0) {
        const double wp = (positions[p] - vi).squaredNorm();
        const double wq = (positions[q] - vi).squaredNorm();
        const Vec3 t = positions[q] - positions[p];
        const double tlen = t.norm();
        if (wp + wq > 0.0 && tlen > 0.0) {
          const Vec3 d = (wp * positions[p] + wq * positions[q]) / (wp + wq) - vi;
          const Vec3 tu = t / tlen;
          r = 2.0 * d.dot(tu) * tu;
        }
      }
    }
    updated[i] = vi + fit + lambda * r;
  }
}

}  // namespace scanmesh
