#include "scanmesh/boundary_curves.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "scanmesh/geometry.h"

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

void smooth_boundary_curves(std::vector<Vec3>& positions, const std::vector<Face>& faces, const Topology& topology,
                            const BoundaryCurves& curves, double window, bool along_too, BoundaryDrift* drift) {
  // Local quadratic least-squares fit of each loop as a function of arc length (a Savitzky-Golay filter):
  // it removes noise along the curve but reproduces lines and circles, so nothing shrinks; a fit never
  // reaches past a corner, and corners themselves are left to update_vertices.
  const auto loops = static_cast<long>(curves.loop_edges.rows());
  std::vector<std::vector<Vec3>> result(curves.loop_edges.rows());
  const bool limited = drift != nullptr && drift->input != nullptr;
  if (limited) drift->stopped.resize(curves.loop_edges.rows(), 0);
#pragma omp parallel
  {
    // Per thread, reused by every loop it takes (this runs in every iteration: nothing per vertex is
    // allocated). Row i of the fit is row_j/row_c[row_start[i] .. row_start[i + 1]).
    std::vector<int> v, row_start, row_j, js;
    std::vector<double> seg, row_c, ws;
    std::vector<Eigen::Vector3d> bases;
    std::vector<Vec3> x, once, residual, correction;
#pragma omp for schedule(dynamic, 1)
    for (long l = 0; l < loops; ++l) {
      const int* edges = curves.loop_edges.begin(l);
      const int ne = curves.loop_edges.size(l);
      const bool closed = curves.loop_closed[l] != 0;
      const int nv = closed ? ne : ne + 1;
      if (ne < 3 || curves.ragged[curves.edges[edges[0]].a] || (limited && drift->stopped[l])) continue;
      v.resize(nv);
      for (int k = 0; k < ne; ++k) {
        v[k] = curves.edges[edges[k]].a;
        if (!closed && k == ne - 1) v[k + 1] = curves.edges[edges[k]].b;
      }
      seg.resize(ne);
      double total = 0.0;
      for (int k = 0; k < ne; ++k) total += seg[k] = (positions[v[(k + 1) % nv]] - positions[v[k]]).norm();
      const double sigma = window * total / ne;
      // The fit is linear in the positions: fitted_i = sum_j c_ij p_j over the window (c from the weighted
      // least-squares solve). Applied once it rounds a curve slightly (a circle loses ~ sigma^4 / R^3 per
      // pass, which adds up over a hundred iterations); "twicing", F(p) + F(p - F(p)), removes that bias to
      // second order while smoothing noise the same.
      row_start.assign(1, 0);
      row_j.clear();
      row_c.clear();
      for (int i = 0; i < nv; ++i) {
        auto end_row = [&] { row_start.push_back(static_cast<int>(row_j.size())); };
        if (curves.corner[v[i]] || !(sigma > 0.0)) {
          end_row();
          continue;
        }
        Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
        js.clear();
        bases.clear();
        ws.clear();
        auto add = [&](int j, double s) {
          const double w = std::exp(-s * s / (2.0 * sigma * sigma));
          const double u = s / sigma;  // scaled for conditioning
          const Eigen::Vector3d basis(1.0, u, u * u);
          a += w * basis * basis.transpose();
          js.push_back(j);
          bases.push_back(basis);
          ws.push_back(w);
        };
        add(i, 0.0);
        for (int dir : {1, -1}) {
          double s = 0.0;
          int j = i;
          for (int step = 1; step < nv / 2 && step <= kBoundaryWindowMaxEdges; ++step) {
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
        if (std::abs(a(0, 1)) > 0.5 * a(0, 0) || a(0, 0) < 2.0) {
          end_row();
          continue;
        }
        Eigen::LDLT<Eigen::Matrix3d> ldlt(a);
        const Eigen::Vector3d e0 = ldlt.solve(Eigen::Vector3d::UnitX());  // (B^T W B)^-1 e0, A symmetric
        if (ldlt.info() == Eigen::Success && e0.allFinite())
          for (std::size_t k = 0; k < js.size(); ++k) {
            row_j.push_back(js[k]);
            row_c.push_back(ws[k] * e0.dot(bases[k]));
          }
        end_row();
      }
      auto fitted_row = [&](int i) { return row_start[i + 1] > row_start[i]; };
      auto apply = [&](const std::vector<Vec3>& in, std::vector<Vec3>& y) {
        y = in;
        for (int i = 0; i < nv; ++i) {
          if (!fitted_row(i)) continue;
          Vec3 sum = Vec3::Zero();
          for (int k = row_start[i]; k < row_start[i + 1]; ++k) sum += row_c[k] * in[row_j[k]];
          y[i] = sum;
        }
      };
      x.resize(nv);
      residual.resize(nv);
      for (int i = 0; i < nv; ++i) x[i] = positions[v[i]];
      apply(x, once);
      for (int i = 0; i < nv; ++i) residual[i] = x[i] - once[i];
      apply(residual, correction);
      // `d` less its part along the chord of vertex i's two curve neighbours (as they are before this pass).
      auto across = [&](int i, Vec3 d) {
        const Vec3 chord = positions[v[(i + 1) % nv]] - positions[v[(i + nv - 1) % nv]];
        const double chord_len = chord.norm();
        if (chord_len > 0.0) {
          const Vec3 along = chord / chord_len;
          d -= d.dot(along) * along;
        }
        return d;
      };
      auto& out = result[l];
      out.resize(nv);
      for (int i = 0; i < nv; ++i) {
        out[i] = positions[v[i]];
        if (!fitted_row(i)) continue;
        const Vec3 fitted = once[i] + correction[i];
        if (!fitted.allFinite()) continue;
        // Move towards the fit, but shorten a move that would squash or fold one of the vertex's triangles
        // (straightening a jagged scan boundary would otherwise flatten the triangles behind it).
        const Vec3 start = positions[v[i]];
        Vec3 move = along_too ? Vec3(fitted - start) : across(i, fitted - start);
        // Only the move across the curve is taken. Along it the fit's target is where the vertex's own
        // (noisy) arc length puts it, so that part is a random step, and over a hundred iterations the
        // steps add up to a walk along the boundary (on the noisy hemisphere its vertices ended 19% farther
        // from their clean positions than interior ones did). Spacing along the curve is update_vertices'
        // job. A fitted vertex has neighbours on both sides (the fit needs support on both). Under impulsive
        // noise (along_too) a vertex that moves is off along the curve by its impulse: it takes the whole move.
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
      if (limited) {
        // The loop's RMS move across the curve since the input. Distinct loops write distinct bytes of
        // `stopped`.
        double sum = 0.0;
        int count = 0;
        for (int i = 0; i < nv; ++i) {
          if (!fitted_row(i)) continue;
          sum += across(i, out[i] - (*drift->input)[v[i]]).squaredNorm();
          ++count;
        }
        if (count > 0 && !(std::sqrt(sum / count) <= drift->max_rms)) {
          out.clear();
          drift->stopped[l] = 1;
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

std::vector<std::uint8_t> boundary_outliers(const std::vector<Vec3>& positions, const BoundaryCurves& curves, double limit_factor) {
  const std::size_t n = positions.size();
  std::vector<std::uint8_t> out(n, 0);
  if (curves.prev.size() != n) return out;
  auto judged = [&](int v) { return v >= 0 && curves.prev[v] >= 0 && curves.next[v] >= 0 && !curves.corner[v] && !curves.ragged[v]; };
  auto second = [&](int v) -> Vec3 { return positions[v] - 0.5 * (positions[curves.prev[v]] + positions[curves.next[v]]); };
  std::vector<double> jump(n, -1.0);
  std::vector<double> valid;
  for (std::size_t i = 0; i < n; ++i) {
    const int v = static_cast<int>(i);
    if (!judged(v) || !judged(curves.prev[v]) || !judged(curves.next[v])) continue;
    jump[i] = (second(v) - 0.5 * (second(curves.prev[v]) + second(curves.next[v]))).norm();
    valid.push_back(jump[i]);
  }
  if (valid.empty()) return out;
  std::nth_element(valid.begin(), valid.begin() + static_cast<long>(valid.size() / 2), valid.end());
  const double limit = limit_factor * valid[valid.size() / 2];
  for (std::size_t i = 0; i < n; ++i)
    out[i] = jump[i] > limit && !(jump[curves.prev[i]] > jump[i]) && !(jump[curves.next[i]] > jump[i]) ? 1 : 0;
  return out;
}

}  // namespace scanmesh
