#include "scanmesh/vertex_update.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <cstdlib>

#include "scanmesh/normal_filtering.h"

namespace scanmesh {

BoundaryCurves build_boundary_curves(const Mesh& mesh, const Topology& topology) {
  BoundaryCurves c;
  const std::size_t nv = mesh.num_vertices();
  c.prev.assign(nv, -1);
  c.next.assign(nv, -1);
  c.vertex_edges.assign(nv, {-1, -1});
  c.loop_edges.offsets.assign(1, 0);
  // The face owning boundary edge a->b: the only face on that edge, looked up around whichever end has
  // fewer faces (the hub of a fan may have thousands).
  auto owning_face = [&](int a, int b) {
    const int hub = topology.vertex_faces.size(a) <= topology.vertex_faces.size(b) ? a : b;
    for (const int* f = topology.vertex_faces.begin(hub); f != topology.vertex_faces.end(hub); ++f)
      for (int k = 0; k < 3; ++k)
        if (mesh.faces[*f][k] == a && mesh.faces[*f][(k + 1) % 3] == b &&
            topology.is_boundary_edge(static_cast<std::size_t>(topology.face_edges[*f][k])))
          return *f;
    return -1;
  };
  // Boundary vertices the loops do not describe (irregular ones) are treated as corners.
  c.corner.assign(nv, 0);
  c.ragged.assign(nv, 0);
  for (std::size_t v = 0; v < nv; ++v) c.corner[v] = topology.boundary_vertex[v];
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
    // Turning angle between consecutive boundary edges at each vertex of the loop.
    std::vector<double> turn1(n, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
      if (!closed && (k == 0 || k + 1 == n)) continue;
      const Vec3 a = mesh.positions[loop[k]] - mesh.positions[loop[(k + n - 1) % n]];
      const Vec3 b = mesh.positions[loop[(k + 1) % n]] - mesh.positions[loop[k]];
      const double la = a.norm(), lb = b.norm();
      if (la > 0.0 && lb > 0.0) turn1[k] = std::acos(std::clamp(a.dot(b) / (la * lb), -1.0, 1.0));
    }
    // A ragged loop: the mean turning angle between consecutive boundary edges exceeds 70 degrees (a pixel
    // staircase turns by 75-130 here; a smooth boundary with noise of 0.3 / 0.7 mean edges by 32 / 69).
    // A staircase has many steps: loops under 8 vertices (a triangle, a quad) are polygons, all corners.
    if (n >= 8) {
      double turn_sum = 0.0;
      std::size_t turns = 0;
      for (std::size_t k = 0; k < n; ++k)
        if (closed || (k > 0 && k + 1 < n)) {
          turn_sum += turn1[k];
          ++turns;
        }
      if (turns > 0 && turn_sum / static_cast<double>(turns) > 70.0 * 3.14159265358979323846 / 180.0)
        for (int v : loop) c.ragged[v] = 1;
    }
    // Corners of the input boundary: the turning angle between the chords to the vertices three steps
    // back and three steps ahead exceeds 50 degrees and no vertex within two steps turns more. Three-edge
    // chords keep noise of a fraction of an edge far from the threshold. Equal chord turns (a coarse
    // polygon, whose sides are as short as the chords) go to the vertex that turns most by itself.
    if (n >= 8) {
      std::vector<double> turn(n, 0.0);
      for (std::size_t k = 0; k < n; ++k) {
        if (!closed && (k < 3 || k + 3 >= n)) continue;
        const Vec3 back = mesh.positions[loop[k]] - mesh.positions[loop[(k + n - 3) % n]];
        const Vec3 ahead = mesh.positions[loop[(k + 3) % n]] - mesh.positions[loop[k]];
        const double lb = back.norm(), la = ahead.norm();
        if (lb > 0.0 && la > 0.0) turn[k] = std::acos(std::clamp(back.dot(ahead) / (lb * la), -1.0, 1.0));
      }
      const double threshold = 50.0 * 3.14159265358979323846 / 180.0;
      for (std::size_t k = 0; k < n; ++k) {
        const int v = loop[k];
        if (c.prev[v] < 0 || c.next[v] < 0) continue;
        bool peak = turn[k] > threshold;
        for (int d = -2; d <= 2 && peak; ++d) {
          const long kk = static_cast<long>(k) + d;
          if (d == 0 || (!closed && (kk < 0 || kk >= static_cast<long>(n)))) continue;
          const auto o = static_cast<std::size_t>((kk + static_cast<long>(n)) % static_cast<long>(n));
          // Turns within 1e-6 rad count as equal, so rounding cannot decide between plateau vertices.
          constexpr double eps = 1e-6;
          const bool beaten = turn[o] > turn[k] + eps || (std::abs(turn[o] - turn[k]) <= eps && turn1[o] > turn1[k] + eps);
          peak = !beaten;
        }
        c.corner[v] = peak ? 1 : 0;
      }
    } else {
      for (int v : loop) c.corner[v] = 1;
    }
  }
  return c;
}

void filter_boundary_normals(const std::vector<Vec3>& positions, BoundaryCurves& curves,
                             const std::vector<Vec3>& filtered_face_normals, double sigma_s,
                             RobustEstimator estimator, double radius_factor) {
  std::vector<Vec3>& filtered = curves.normals;
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

Adjacency fidelity_neighbours(const Mesh& mesh, const Topology& topology) {
  std::vector<std::uint8_t> solid(mesh.num_faces(), 0);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const Vec3& a = mesh.positions[mesh.faces[f][0]];
    const Vec3& b = mesh.positions[mesh.faces[f][1]];
    const Vec3& c = mesh.positions[mesh.faces[f][2]];
    const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    solid[f] = (b - a).cross(c - a).norm() > 1e-12 * longest2 ? 1 : 0;
  }
  const std::size_t nv = mesh.num_vertices();
  std::vector<std::uint8_t> keep(topology.edges.size(), 0);
  std::vector<int> count(nv + 1, 0);
  for (std::size_t e = 0; e < topology.edges.size(); ++e) {
    const auto [a, b] = topology.edges[e];
    if (a == b) continue;
    for (const int* f = topology.edge_faces.begin(e); f != topology.edge_faces.end(e) && !keep[e]; ++f) keep[e] = solid[*f];
    if (keep[e]) ++count[a + 1], ++count[b + 1];
  }
  Adjacency n;
  n.offsets.resize(nv + 1);
  for (std::size_t v = 0; v < nv; ++v) count[v + 1] += count[v];
  n.offsets.assign(count.begin(), count.end());
  n.indices.resize(static_cast<std::size_t>(n.offsets.back()));
  std::vector<int> fill(n.offsets.begin(), n.offsets.end() - 1);
  // Edges are sorted by (smaller, larger), so rows come out ascending when filled in two sweeps.
  for (std::size_t e = 0; e < topology.edges.size(); ++e)
    if (keep[e]) n.indices[fill[topology.edges[e][1]]++] = topology.edges[e][0];
  for (std::size_t e = 0; e < topology.edges.size(); ++e)
    if (keep[e]) n.indices[fill[topology.edges[e][0]]++] = topology.edges[e][1];
  return n;
}

void update_vertices(const std::vector<Vec3>& positions, const Topology& topology, const Adjacency& neighbours,
                     const FaceGeometry& geometry, const std::vector<Vec3>& filtered_normals, double lambda,
                     const BoundaryCurves* boundary, bool feature_aware, std::vector<Vec3>& updated) {
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

    const bool on_boundary = boundary != nullptr && topology.boundary_vertex[i] != 0 && !boundary->ragged[i];
    if (on_boundary && boundary->corner[i]) {
      // A corner of the boundary curve (or an irregular boundary vertex) has too few curve neighbours to
      // fit a curve: it follows its faces' filtered normals only.
      updated[i] = vi + fit;
      continue;
    }
    if (on_boundary) {
      // A boundary vertex sees faces on one side only: fitting it to their filtered normals (tilted
      // towards the interior on curved surfaces) makes the boundary flare out, and its half-sized
      // neighbourhood leaves it noisy. It is denoised as a point of its boundary curve instead
      // (smooth_boundary_curves); here it only evens out its edges along the curve.
      Vec3 r = Vec3::Zero();
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
      updated[i] = vi + lambda * r;
      continue;
    }
    // D_i with w_ij = |v_i - v_j|^2, then R_i = D_i + tangential part of D_i.
    Vec3 r = Vec3::Zero();
    Vec3 wsum = Vec3::Zero();
    double w = 0.0;
    for (const int* j = neighbours.begin(i); j != neighbours.end(i); ++j) {
      const double wij = (positions[*j] - vi).squaredNorm();
      wsum += wij * positions[*j];
      w += wij;
    }
    if (w > 0.0) {
      const Vec3 d = wsum / w - vi;
      r = d + (d - d.dot(vertex_normal) * vertex_normal);
      if (feature_aware) {
        // Normal tensor of the filtered normals: one large eigenvalue on smooth parts, two along a
        // sharp edge, three at a corner. On edges only the move along the edge is kept, at corners none,
        // so the fidelity term evens out triangles without rounding features.
        Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
        double area = 0.0;
        for (const int* f = topology.vertex_faces.begin(i); f != topology.vertex_faces.end(i); ++f) {
          tensor += geometry.areas[*f] * filtered_normals[*f] * filtered_normals[*f].transpose();
          area += geometry.areas[*f];
        }
        if (area > 0.0) {
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
          es.computeDirect(tensor / area);
          const Vec3 ev = es.eigenvalues();  // ascending
          constexpr double kFeature = 0.1;
          if (ev[0] >= kFeature) {
            r.setZero();
          } else if (ev[1] >= kFeature) {
            const Vec3 t = es.eigenvectors().col(0);
            r = 2.0 * d.dot(t) * t;
          }
        }
      }
    }
    updated[i] = vi + fit + lambda * r;
  }
}

void smooth_boundary_curves(std::vector<Vec3>& positions, const std::vector<Face>& faces, const Topology& topology,
                            const BoundaryCurves& curves, double window) {
  // Local quadratic least-squares fit of each loop as a function of arc length (a Savitzky-Golay filter):
  // it removes noise along the curve but reproduces lines and circles, so nothing shrinks; a fit never
  // reaches past a corner, and corners themselves are left to update_vertices.
  const auto loops = static_cast<long>(curves.loop_edges.rows());
  std::vector<std::vector<Vec3>> result(curves.loop_edges.rows());
#pragma omp parallel for schedule(dynamic, 1)
  for (long l = 0; l < loops; ++l) {
    const int* edges = curves.loop_edges.begin(l);
    const int ne = curves.loop_edges.size(l);
    const bool closed = curves.loop_closed[l] != 0;
    const int nv = closed ? ne : ne + 1;
    if (ne < 3 || curves.ragged[curves.edges[edges[0]].a]) continue;
    std::vector<int> v(nv);
    for (int k = 0; k < ne; ++k) {
      v[k] = curves.edges[edges[k]].a;
      if (!closed && k == ne - 1) v[k + 1] = curves.edges[edges[k]].b;
    }
    std::vector<double> seg(ne);
    double total = 0.0;
    for (int k = 0; k < ne; ++k) total += seg[k] = (positions[v[(k + 1) % nv]] - positions[v[k]]).norm();
    const double sigma = window * total / ne;
    auto& out = result[l];
    out.resize(nv);
    for (int i = 0; i < nv; ++i) {
      out[i] = positions[v[i]];
      if (curves.corner[v[i]] || !(sigma > 0.0)) continue;
      Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
      Eigen::Matrix3d b = Eigen::Matrix3d::Zero();  // columns: x, y, z right-hand sides
      auto add = [&](int j, double s) {
        const double w = std::exp(-s * s / (2.0 * sigma * sigma));
        const double u = s / sigma;  // scaled for conditioning
        const Eigen::Vector3d basis(1.0, u, u * u);
        a += w * basis * basis.transpose();
        b += w * basis * positions[v[j]].transpose();
      };
      add(i, 0.0);
      for (int dir : {1, -1}) {
        double s = 0.0;
        int j = i;
        for (int step = 1; step < nv / 2; ++step) {
          const int next = j + dir;
          if (!closed && (next < 0 || next >= nv)) break;
          const int jn = (next + nv) % nv;
          s += seg[dir > 0 ? j : jn];
          if (s > 3.0 * sigma) break;
          j = jn;
          add(j, dir * s);
          if (curves.corner[v[j]]) break;  // a corner ends the stretch the fit may use
        }
      }
      // Needs support on both sides to be a fit rather than an extrapolation.
      if (std::abs(a(0, 1)) > 0.5 * a(0, 0) || a(0, 0) < 2.0) continue;
      Eigen::LDLT<Eigen::Matrix3d> ldlt(a);
      const Eigen::Matrix3d coeff = ldlt.solve(b);
      const Vec3 fitted = coeff.row(0).transpose();
      if (ldlt.info() != Eigen::Success || !fitted.allFinite()) continue;
      // Move towards the fit, but shorten a move that would squash or fold one of the vertex's triangles
      // (straightening a jagged scan boundary would otherwise flatten the triangles behind it).
      const Vec3 start = positions[v[i]];
      Vec3 move = fitted - start;
      for (int attempt = 0; attempt < 4; ++attempt, move *= 0.5) {
        bool ok = true;
        for (const int* f = topology.vertex_faces.begin(v[i]); ok && f != topology.vertex_faces.end(v[i]); ++f) {
          const Face& t = faces[*f];
          Vec3 p[3];
          for (int k = 0; k < 3; ++k) p[k] = t[k] == v[i] ? Vec3(start + move) : positions[t[k]];
          const Vec3 before = (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]);
          const Vec3 after = (p[1] - p[0]).cross(p[2] - p[0]);
          // The triangle may turn by less than 45 degrees, and its shape (circumradius / shortest edge)
          // must stay below 1.5 or not get worse.
          ok = after.dot(before) >= std::cos(0.7853981633974483) * after.norm() * before.norm() &&
               triangle_shape(p[0], p[1], p[2]) <= std::max(1.5, triangle_shape(positions[t[0]], positions[t[1]], positions[t[2]]));
        }
        if (ok) {
          out[i] = start + move;
          break;
        }
      }
    }
  }
  // Loops are disjoint, so writing back after all fits keeps the result independent of thread order.
  for (long l = 0; l < loops; ++l) {
    if (result[l].empty()) continue;
    const int* edges = curves.loop_edges.begin(l);
    const int ne = curves.loop_edges.size(l);
    for (int k = 0; k < ne; ++k) positions[curves.edges[edges[k]].a] = result[l][k];
    if (curves.loop_closed[l] == 0) positions[curves.edges[edges[ne - 1]].b] = result[l][ne];
  }
}

}  // namespace scanmesh
