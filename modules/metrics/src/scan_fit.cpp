// Scan fit: distances from the input points to the mesh, coverage, pieces, and boundary loops told apart
// into rims, gaps in the data and holes left by the meshing.
#include "scanmesh/scan_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>

#include "scanmesh/closest_point.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/geometry.h"
#include "scanmesh/nearest_points.h"
#include "scanmesh/neighbourhoods.h"
#include "scanmesh/topology.h"

namespace scanmesh {
namespace {

// Piece label of every face (pieces joined through shared vertices), labels 0.. in order of first face.
std::vector<int> face_pieces(const Mesh& mesh, std::size_t& count) {
  const std::vector<int> piece = vertex_pieces(mesh);
  std::vector<int> label(mesh.num_vertices(), -1), out(mesh.num_faces());
  count = 0;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const int root = piece[mesh.faces[f][0]];
    if (label[root] < 0) label[root] = static_cast<int>(count++);
    out[f] = label[root];
  }
  return out;
}

// Points left out near a loop's probes that do not make it a hole: one or two are stray points (noise the
// outlier removal kept, a point the denoised surface moved away from), measured surface takes three.
constexpr std::size_t kStrays = 2;

// Closed boundary loops, also through pinch vertices (where several boundary edges meet, which
// Topology::boundary_loops does not chain): boundary edges directed by their face, then split into cycles
// by always leaving a vertex on its lowest unused outgoing boundary edge. Chains that do not close (faces
// of opposite orientation) are dropped.
std::vector<std::vector<int>> closed_boundary_loops(const Mesh& mesh, const Topology& topo) {
  std::vector<std::vector<std::pair<int, int>>> out(mesh.num_vertices());  // (target, edge id)
  std::size_t id = 0;
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    if (topo.edge_faces.size(e) != 1) continue;
    const Face& f = mesh.faces[topo.edge_faces.begin(e)[0]];
    const auto [a, b] = topo.edges[e];
    bool ab = false;
    for (int k = 0; k < 3; ++k) ab = ab || (f[k] == a && f[(k + 1) % 3] == b);
    // The face runs a -> b along the edge; the boundary is walked the other way round, b -> a.
    if (ab) out[b].emplace_back(a, static_cast<int>(id++));
    else out[a].emplace_back(b, static_cast<int>(id++));
  }
  for (auto& o : out) std::sort(o.begin(), o.end());
  std::vector<char> used(id, 0);
  std::vector<std::size_t> next_out(mesh.num_vertices(), 0);
  std::vector<std::vector<int>> loops;
  for (std::size_t start = 0; start < mesh.num_vertices(); ++start) {
    while (next_out[start] < out[start].size()) {
      std::vector<int> loop;
      int v = static_cast<int>(start);
      bool closed = false;
      while (true) {
        std::size_t& k = next_out[v];
        while (k < out[v].size() && used[out[v][k].second]) ++k;
        if (k == out[v].size()) break;
        used[out[v][k].second] = 1;
        loop.push_back(v);
        v = out[v][k].first;
        if (v == static_cast<int>(start)) {
          closed = true;
          break;
        }
      }
      if (closed && loop.size() >= 3) loops.push_back(std::move(loop));
    }
  }
  return loops;
}

// The points' scatter across the surface (a standard deviation, scene units), from the signed distances
// of points whose feet (closest points on the mesh) are neighbours: the difference of two independent
// noisy distances has twice the variance, and its median absolute value is 0.6745 x its deviation. Pairs
// are formed on the surface (by the feet), not in space, so that points at the same height do not pair up
// preferentially where the noise is wider than the spacing. `signed_distance` is NaN where no sign is known.
double scatter_across_surface(const std::vector<Vec3>& feet, const std::vector<double>& signed_distance, double spacing) {
  if (feet.size() < 8) return 0.0;
  const NearestPoints index(feet);
  const auto n = static_cast<long>(feet.size());
  std::vector<double> diff(feet.size(), std::numeric_limits<double>::quiet_NaN());
#pragma omp parallel for schedule(dynamic, 256)
  for (long i = 0; i < n; ++i) {
    if (std::isnan(signed_distance[i])) continue;
    thread_local std::vector<int> near;
    index.nearest(feet[i], 4, near);
    for (int j : near) {
      // Coincident feet (a duplicate point, points past a rim projecting onto one corner) are not a pair.
      const double apart = (feet[j] - feet[i]).norm();
      if (j == i || std::isnan(signed_distance[j]) || !(apart > 1e-9 * spacing) || apart > 2.0 * spacing) continue;
      diff[i] = std::abs(signed_distance[i] - signed_distance[j]);
      break;
    }
  }
  diff.erase(std::remove_if(diff.begin(), diff.end(), [](double d) { return std::isnan(d); }), diff.end());
  if (diff.size() < 8) return 0.0;
  const auto mid = diff.begin() + static_cast<long>(diff.size() / 2);
  std::nth_element(diff.begin(), mid, diff.end());
  return *mid / 0.6745 / std::sqrt(2.0);
}

// Faces of the pieces lying over a larger piece (ScanFit::layered_pieces), from each face's piece label and
// the pieces' face counts; `count` is set to the number of such pieces. Each vertex of a piece other than
// the largest looks at its 32 nearest vertices for one of a larger piece within `radius`: on a surface
// meshed twice its own layer holds about a dozen vertices that close and the other layer as many again.
std::vector<std::uint8_t> layered_faces(const Mesh& mesh, const std::vector<int>& face_piece, const std::vector<std::size_t>& piece_faces,
                                        double radius, std::size_t& count) {
  std::vector<std::uint8_t> out(mesh.num_faces(), 0);
  count = 0;
  if (piece_faces.size() < 2) return out;
  // Rank 0 is the largest piece; equal pieces in the order of their first face.
  std::vector<int> order(piece_faces.size()), rank(piece_faces.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return piece_faces[a] > piece_faces[b]; });
  for (std::size_t r = 0; r < order.size(); ++r) rank[order[r]] = static_cast<int>(r);
  std::vector<int> vertex_rank(mesh.num_vertices(), -1);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f)
    for (int v : mesh.faces[f]) vertex_rank[v] = rank[face_piece[f]];
  std::vector<Vec3> used;
  std::vector<int> used_rank, queries;
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    if (vertex_rank[v] < 0) continue;
    if (vertex_rank[v] > 0) queries.push_back(static_cast<int>(used.size()));
    used.push_back(mesh.positions[v]);
    used_rank.push_back(vertex_rank[v]);
  }
  const NearestPoints index(used);
  std::vector<char> over(used.size(), 0);
  const auto n = static_cast<long>(queries.size());
  const double r2 = radius * radius;
#pragma omp parallel for schedule(dynamic, 256)
  for (long k = 0; k < n; ++k) {
    thread_local std::vector<int> near;
    const int q = queries[static_cast<std::size_t>(k)];
    index.nearest(used[q], 32, near);
    for (int j : near)
      if (used_rank[j] < used_rank[q] && (used[j] - used[q]).squaredNorm() <= r2) {
        over[q] = 1;
        break;
      }
  }
  std::vector<std::size_t> vertices(piece_faces.size(), 0), lying_over(piece_faces.size(), 0);
  for (std::size_t i = 0; i < used.size(); ++i) {
    ++vertices[used_rank[i]];
    lying_over[used_rank[i]] += over[i];
  }
  std::vector<char> dropped(piece_faces.size(), 0);
  for (std::size_t r = 1; r < piece_faces.size(); ++r)
    if (2 * lying_over[r] >= vertices[r]) {
      dropped[r] = 1;
      ++count;
    }
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) out[f] = dropped[rank[face_piece[f]]];
  return out;
}

}  // namespace

std::string coverage_radius_words(const ScanFit& fit) {
  if (!(fit.spacing > 0.0) || fit.coverage_radius <= 2.0 * fit.spacing) return "2 spacings";
  char b[128];
  std::snprintf(b, sizeof b, "3 x the points' scatter across the surface, %.3g spacings", fit.coverage_radius / fit.spacing);
  return b;
}

ScanFit measure_scan_fit(const Mesh& mesh, const std::vector<Vec3>& points, double spacing, bool from_grid, const ScanFit* as_meshed) {
  ScanFit fit;
  fit.spacing = spacing;
  fit.coverage_radius = 2.0 * spacing;
  std::vector<Vec3> finite;
  finite.reserve(points.size());
  for (const Vec3& p : points)
    if (p.allFinite()) finite.push_back(p);
  fit.points = finite.size();
  if (mesh.faces.empty() || finite.empty()) {
    fit.point_distance.assign(finite.size(), std::numeric_limits<double>::infinity());
    fit.points_left_out = finite.size();
    return fit;
  }

  // Distances of the points to the surface, signed by the normal of the face each is closest to, and
  // the scatter across the surface they show: where the noise is wider than 2 spacings / 3, the coverage
  // radius grows to 3 x that scatter (the surface itself would leave a Gaussian scan's tails out).
  {
    const ClosestPointIndex index(mesh);
    fit.point_distance.resize(finite.size());
    std::vector<Vec3> feet(finite.size());
    std::vector<double> signed_distance(finite.size());
    const auto n = static_cast<long>(finite.size());
#pragma omp parallel for schedule(dynamic, 256)
    for (long i = 0; i < n; ++i) {
      const ClosestPointIndex::Hit hit = index.closest(finite[i]);
      fit.point_distance[i] = hit.distance;
      feet[i] = hit.point;
      Vec3 normal = Vec3::Zero();
      if (hit.face >= 0) {
        const Face& f = mesh.faces[static_cast<std::size_t>(hit.face)];
        normal = triangle_normal(mesh.positions[f[0]], mesh.positions[f[1]], mesh.positions[f[2]]);
      }
      const double d = (finite[i] - hit.point).dot(normal);
      signed_distance[i] = normal.isZero() || !std::isfinite(d) ? std::numeric_limits<double>::quiet_NaN() : d;
    }
    fit.scatter = scatter_across_surface(feet, signed_distance, spacing);
    fit.coverage_radius = std::max(2.0 * spacing, 3.0 * fit.scatter);
  }
  std::vector<double> sorted = fit.point_distance;
  std::sort(sorted.begin(), sorted.end());
  fit.distance_mean = std::accumulate(sorted.begin(), sorted.end(), 0.0) / static_cast<double>(sorted.size());
  fit.distance_p95 = sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(0.95 * static_cast<double>(sorted.size())))];
  fit.distance_max = sorted.back();
  for (double d : fit.point_distance) fit.points_left_out += d > fit.coverage_radius ? 1 : 0;
  fit.coverage = 1.0 - static_cast<double>(fit.points_left_out) / static_cast<double>(finite.size());

  // Pieces.
  const std::vector<int> piece = face_pieces(mesh, fit.pieces);
  std::vector<std::size_t> piece_faces(fit.pieces, 0);
  for (int p : piece) ++piece_faces[p];
  fit.main_piece_share = static_cast<double>(*std::max_element(piece_faces.begin(), piece_faces.end())) /
                         static_cast<double>(mesh.num_faces());
  fit.layered_faces = layered_faces(mesh, piece, piece_faces, fit.coverage_radius, fit.layered_pieces);
  fit.layered_share = static_cast<double>(std::count(fit.layered_faces.begin(), fit.layered_faces.end(), std::uint8_t{1})) /
                      static_cast<double>(mesh.num_faces());
  if (fit.layered_pieces == 0) std::vector<std::uint8_t>().swap(fit.layered_faces);

  // Boundary loops: the longest of each piece is its rim; another loop is a gap when the region it
  // encloses holds no points (the scanner saw nothing there), else a hole the meshing left. The region is
  // probed at the loop's centroid and halfway from there to each corner: more than kStrays points that the
  // mesh leaves out (farther than the coverage radius from it) within 1.5 spacings of the probes mean
  // measured surface inside the loop. A loop too small to enclose an empty region (every probe within 1.5
  // spacings of a point) is a hole as well. A gap whose probe lies off the mesh beside a point the mesh
  // covers is marked `points_beside`: noise beside the surface, or a sparsely sampled curve the loop cuts
  // across. A loop `as_meshed` has as well (the same vertices in the same order) keeps the kind it had
  // there, and the rims are chosen among the other loops of pieces whose rim is not among those.
  const Topology topo = build_topology(mesh);
  fit.inconsistent_edges = topology_stats(mesh).inconsistent_edges;
  const std::vector<std::vector<int>> loops = closed_boundary_loops(mesh, topo);
  std::map<std::pair<int, std::size_t>, std::vector<const BoundaryLoopFit*>> meshed_loops;  // by first vertex and length
  if (as_meshed != nullptr)
    for (const auto& l : as_meshed->loops)
      if (!l.ring.empty()) meshed_loops[{l.ring.front(), l.ring.size()}].push_back(&l);
  std::vector<char> inherited(loops.size(), 0);
  std::vector<char> piece_has_rim(fit.pieces, 0);
  for (std::size_t i = 0; i < loops.size(); ++i) {
    BoundaryLoopFit b;
    b.vertices = loops[i].size();
    for (std::size_t k = 0; k < b.vertices; ++k) b.perimeter += (mesh.positions[loops[i][k]] - mesh.positions[loops[i][(k + 1) % b.vertices]]).norm();
    b.ring = loops[i];
    if (const auto it = meshed_loops.find({b.ring.front(), b.vertices}); it != meshed_loops.end())
      for (const BoundaryLoopFit* m : it->second)
        if (m->ring == b.ring) {
          b.kind = m->kind;
          b.points_beside = m->points_beside;
          inherited[i] = 1;
          if (b.kind == BoundaryLoopFit::Kind::rim) piece_has_rim[piece[topo.vertex_faces.begin(b.ring.front())[0]]] = 1;
        }
    fit.loops.push_back(std::move(b));
  }
  std::vector<int> rim_of_piece(fit.pieces, -1);
  std::vector<double> rim_length(fit.pieces, -1.0);
  for (std::size_t i = 0; i < fit.loops.size(); ++i) {
    const int p = piece[topo.vertex_faces.begin(loops[i].front())[0]];
    if (!inherited[i] && !piece_has_rim[p] && fit.loops[i].perimeter > rim_length[p]) {
      rim_length[p] = fit.loops[i].perimeter;
      rim_of_piece[p] = static_cast<int>(i);
    }
  }
  std::vector<char> is_rim(fit.loops.size(), 0);
  for (int r : rim_of_piece)
    if (r >= 0) is_rim[r] = 1;
  // Probes of all loops to be judged, answered in one batch.
  std::vector<Vec3> probes;
  std::vector<std::size_t> probe_start(fit.loops.size() + 1, 0);
  for (std::size_t i = 0; i < fit.loops.size(); ++i) {
    probe_start[i] = probes.size();
    if (inherited[i] || is_rim[i] || from_grid) continue;
    const auto& loop = loops[i];
    Vec3 c = Vec3::Zero();
    for (int v : loop) c += mesh.positions[v];
    c /= static_cast<double>(loop.size());
    probes.push_back(c);
    const std::size_t step = std::max<std::size_t>(1, loop.size() / 16);
    for (std::size_t k = 0; k < loop.size(); k += step) probes.push_back(0.5 * (c + mesh.positions[loop[k]]));
  }
  probe_start[fit.loops.size()] = probes.size();
  // Each probe's points within 1.5 spacings: is there one, and which of them are left out (at most
  // kStrays + 1 recorded). Only the 16 nearest are looked at, so a pile of coincident points costs each
  // probe no more than that.
  std::vector<char> near_point(probes.size(), 0);
  std::vector<std::array<int, kStrays + 1>> near_left_out(probes.size());
  for (auto& l : near_left_out) l.fill(-1);
  if (!probes.empty()) {
    const NearestPoints index(finite);
    const auto n = static_cast<long>(probes.size());
#pragma omp parallel for schedule(dynamic, 64)
    for (long k = 0; k < n; ++k) {
      thread_local std::vector<int> near;
      index.nearest(probes[k], 16, near);
      for (int j : near) {
        if ((finite[j] - probes[k]).norm() > 1.5 * spacing) continue;
        near_point[k] = 1;
        if (fit.point_distance[j] > fit.coverage_radius)
          for (int& slot : near_left_out[k])
            if (slot < 0) {
              slot = j;
              break;
            }
      }
    }
  }
  const ClosestPointIndex surface(mesh);
  for (std::size_t i = 0; i < fit.loops.size(); ++i) {
    BoundaryLoopFit& b = fit.loops[i];
    if (inherited[i]) {
      switch (b.kind) {
        case BoundaryLoopFit::Kind::rim: ++fit.rims; break;
        case BoundaryLoopFit::Kind::gap: ++fit.gaps; break;
        case BoundaryLoopFit::Kind::hole:
          ++fit.holes;
          fit.largest_hole = std::max(fit.largest_hole, b.perimeter);
          break;
      }
      continue;
    }
    if (is_rim[i]) {
      b.kind = BoundaryLoopFit::Kind::rim;
      ++fit.rims;
      continue;
    }
    if (from_grid) {
      b.kind = BoundaryLoopFit::Kind::gap;
      ++fit.gaps;
      continue;
    }
    bool all_near = true;
    std::vector<int> left_out;  // distinct points left out near the loop's probes
    for (std::size_t k = probe_start[i]; k < probe_start[i + 1]; ++k) {
      all_near = all_near && near_point[k];
      for (int j : near_left_out[k])
        if (j >= 0 && std::find(left_out.begin(), left_out.end(), j) == left_out.end()) left_out.push_back(j);
    }
    const bool data_inside = left_out.size() > kStrays;
    if (data_inside || all_near) {
      b.kind = BoundaryLoopFit::Kind::hole;
      ++fit.holes;
      fit.largest_hole = std::max(fit.largest_hole, b.perimeter);
    } else {
      b.kind = BoundaryLoopFit::Kind::gap;
      ++fit.gaps;
      for (std::size_t k = probe_start[i]; k < probe_start[i + 1] && !b.points_beside; ++k)
        b.points_beside = near_point[k] && surface.closest(probes[k]).distance > 0.5 * spacing;
    }
  }
  return fit;
}

std::vector<std::string> scan_fit_problems(const ScanFit& fit, const ScanFitLimits& limits) {
  std::vector<std::string> out;
  char buf[256];
  if (fit.coverage < limits.min_coverage) {
    std::snprintf(buf, sizeof buf, "the mesh leaves %.1f%% of the points out (%zu farther than %s; at most %.1f%% expected)",
                  100.0 * (1.0 - fit.coverage), fit.points_left_out, coverage_radius_words(fit).c_str(), 100.0 * (1.0 - limits.min_coverage));
    out.emplace_back(buf);
  }
  std::size_t big = 0;
  for (const auto& l : fit.loops)
    big += l.kind == BoundaryLoopFit::Kind::hole && l.perimeter >= limits.min_hole_perimeter * fit.spacing ? 1 : 0;
  if (big > limits.max_holes) {
    std::snprintf(buf, sizeof buf, "%zu hole%s where the scan has points (the largest %.3g spacings around)", big, big == 1 ? "" : "s",
                  fit.spacing > 0 ? fit.largest_hole / fit.spacing : 0.0);
    out.emplace_back(buf);
  }
  if (fit.layered_share > limits.max_layered_share) {
    std::snprintf(buf, sizeof buf,
                  "%zu piece%s holding %.1f%% of the faces lie%s over another piece (at least half of each within %s of it): the "
                  "surface is meshed twice, as when both sides of a thin sheet or shell were scanned; at most %.1f%% expected",
                  fit.layered_pieces, fit.layered_pieces == 1 ? "" : "s", 100.0 * fit.layered_share, fit.layered_pieces == 1 ? "s" : "",
                  coverage_radius_words(fit).c_str(), 100.0 * limits.max_layered_share);
    out.emplace_back(buf);
  }
  if (fit.inconsistent_edges > limits.max_inconsistent_edges) {
    std::snprintf(buf, sizeof buf, "%zu edges between faces of opposite orientation", fit.inconsistent_edges);
    out.emplace_back(buf);
  }
  return out;
}

void write_json(JsonWriter& w, const ScanFit& f) {
  w.begin_object();
  w.field("points", f.points).field("spacing", f.spacing).field("coverage", f.coverage).field("coverage_radius", f.coverage_radius);
  w.field("scatter", f.scatter);
  w.field("points_left_out", f.points_left_out);
  w.field("distance_mean", f.distance_mean).field("distance_p95", f.distance_p95).field("distance_max", f.distance_max);
  w.field("pieces", f.pieces).field("main_piece_share", f.main_piece_share);
  w.field("layered_pieces", f.layered_pieces).field("layered_share", f.layered_share);
  w.field("rims", f.rims).field("holes", f.holes).field("gaps", f.gaps).field("largest_hole", f.largest_hole);
  w.field("inconsistent_edges", f.inconsistent_edges);
  w.key("problems").begin_array();
  for (const auto& p : scan_fit_problems(f)) w.value(p);
  w.end_array();
  w.end_object();
}

std::string scan_fit_summary(const ScanFit& fit) {
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "coverage %.1f%% (%zu points left out); point-to-mesh distance mean %.3g, p95 %.3g, max %.3g; %zu piece%s; %zu hole%s, "
                "%zu gap%s in the data",
                100.0 * fit.coverage, fit.points_left_out, fit.distance_mean, fit.distance_p95, fit.distance_max, fit.pieces,
                fit.pieces == 1 ? "" : "s", fit.holes, fit.holes == 1 ? "" : "s", fit.gaps, fit.gaps == 1 ? "" : "s");
  return buf;
}

}  // namespace scanmesh
