#include "scanmesh/evaluate.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scanmesh/closest_point.h"
#include "scanmesh/json.h"
#include "scanmesh/neighbourhoods.h"
#include "scanmesh/scan_fit.h"
#include "scanmesh/geometry.h"
#include "scanmesh/topology.h"

namespace scanmesh {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Distances from every vertex of `from` to the surface `to`.
std::vector<double> distances_to(const Mesh& from, const Mesh& to) {
  const std::vector<ClosestPointIndex::Hit> hits = ClosestPointIndex(to).closest_all(from.positions);
  std::vector<double> d(hits.size());
  for (std::size_t i = 0; i < hits.size(); ++i) d[i] = hits[i].distance;
  return d;
}

bool is_closed(const TopologyStats& t) { return t.boundary_edges == 0 && t.nonmanifold_edges == 0 && t.faces > 0; }

TopologyStats stats_of(const Mesh& mesh, const Topology& topo) {
  TopologyStats s;
  s.vertices = mesh.num_vertices();
  s.faces = mesh.num_faces();
  s.edges = topo.edges.size();
  s.boundary_edges = topo.num_boundary_edges();
  s.boundary_loops = topo.boundary_loops.size();
  s.nonmanifold_edges = topo.num_nonmanifold_edges();
  s.components = count_components(mesh, topo);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) s.isolated_vertices += topo.vertex_faces.size(v) == 0 ? 1 : 0;
  for (const Face& f : mesh.faces) {
    double area = 0.0;
    triangle_normal(mesh.positions[f[0]], mesh.positions[f[1]], mesh.positions[f[2]], &area);
    s.degenerate_faces += area > 0.0 ? 0 : 1;
  }
  for (const auto& p : mesh.positions) s.nonfinite_vertices += p.allFinite() ? 0 : 1;
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    if (topo.edge_faces.size(e) != 2) continue;
    const auto [a, b] = topo.edges[e];
    int dir[2];
    for (int k = 0; k < 2; ++k) {
      const Face& f = mesh.faces[topo.edge_faces.begin(e)[k]];
      dir[k] = 0;
      for (int i = 0; i < 3; ++i) dir[k] += (f[i] == a && f[(i + 1) % 3] == b) ? 1 : (f[i] == b && f[(i + 1) % 3] == a) ? -1 : 0;
    }
    s.inconsistent_edges += dir[0] == dir[1] ? 1 : 0;
  }
  return s;
}

}  // namespace

TopologyStats topology_stats(const Mesh& mesh) { return stats_of(mesh, build_topology(mesh)); }

double signed_volume(const Mesh& mesh) {
  double v = 0.0;
  for (const Face& f : mesh.faces)
    v += mesh.positions[f[0]].dot(mesh.positions[f[1]].cross(mesh.positions[f[2]]));
  return v / 6.0;
}

MeshMetrics evaluate(const Mesh& mesh, const Mesh* reference) {
  MeshMetrics m;
  const Topology topo = build_topology(mesh);  // built once, shared by every measure below
  m.topology = stats_of(mesh, topo);
  m.bbox_diagonal = bbox_diagonal(mesh.positions);
  m.mean_edge_length = mean_edge_length(mesh, topo);

  const auto nf = static_cast<long>(mesh.num_faces());
  m.face_quality.resize(mesh.num_faces());
#pragma omp parallel for schedule(static)
  for (long f = 0; f < nf; ++f) {
    const Face& t = mesh.faces[f];
    m.face_quality[f] = triangle_shape(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
  }
  std::size_t finite = 0;
  for (double q : m.face_quality)
    if (std::isfinite(q)) {
      m.quality_mean += q;
      m.quality_max = std::max(m.quality_max, q);
      ++finite;
    }
  if (finite > 0) m.quality_mean /= static_cast<double>(finite);

  FaceGeometry g, gr;
  compute_face_geometry(mesh.positions, mesh.faces, g);
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    if (topo.edge_faces.size(e) != 2) continue;
    const int a = topo.edge_faces.begin(e)[0], b = topo.edge_faces.begin(e)[1];
    m.manifold_edges.push_back(topo.edges[e]);
    m.dihedral_deg.push_back(std::acos(std::clamp(g.normals[a].dot(g.normals[b]), -1.0, 1.0)) * 180.0 / kPi);
  }

  if (reference == nullptr) return m;
  m.has_reference = true;
  m.same_connectivity = reference->faces == mesh.faces;
  if (m.same_connectivity) {
    compute_face_geometry(reference->positions, reference->faces, gr);
    m.face_angle_error.resize(mesh.num_faces());
#pragma omp parallel for schedule(static)
    for (long f = 0; f < nf; ++f) {
      const double c = std::clamp(g.normals[f].dot(gr.normals[f]), -1.0, 1.0);
      m.face_angle_error[f] = std::acos(c) * 180.0 / kPi;
    }
    for (double a : m.face_angle_error) {
      m.msae_deg += a;
      m.flipped_faces += a > 90.0 ? 1 : 0;
    }
    if (nf > 0) m.msae_deg /= static_cast<double>(nf);
  }

  m.vertex_distance = distances_to(mesh, *reference);
  double wsum = 0.0, wd2 = 0.0;
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    double area = 0.0;
    for (const int* f = topo.vertex_faces.begin(v); f != topo.vertex_faces.end(v); ++f) area += g.areas[*f];
    const double d = m.vertex_distance[v];
    wsum += area;
    wd2 += area * d * d;
    m.distance_mean += d;
    m.distance_rms += d * d;
    m.hausdorff_to_reference = std::max(m.hausdorff_to_reference, d);
  }
  const double nv = static_cast<double>(std::max<std::size_t>(1, mesh.num_vertices()));
  m.distance_mean /= nv;
  m.distance_rms = std::sqrt(m.distance_rms / nv);
  m.ev = wsum > 0.0 ? std::sqrt(wd2 / wsum) : 0.0;
  const double ref_diag = bbox_diagonal(reference->positions);
  m.ev_relative = ref_diag > 0.0 ? m.ev / ref_diag : 0.0;
  for (double d : distances_to(*reference, mesh)) m.hausdorff_from_reference = std::max(m.hausdorff_from_reference, d);
  m.hausdorff = std::max(m.hausdorff_to_reference, m.hausdorff_from_reference);

  const TopologyStats rt = topology_stats(*reference);
  if (is_closed(m.topology) && is_closed(rt)) {
    const double vr = signed_volume(*reference);
    if (vr != 0.0) m.volume_change = (signed_volume(mesh) - vr) / vr;
  }
  return m;
}

double nearest_face_normal_error(const Mesh& mesh, const Mesh& reference) {
  ClosestPointIndex index(reference);
  FaceGeometry g, gr;
  compute_face_geometry(mesh.positions, mesh.faces, g);
  compute_face_geometry(reference.positions, reference.faces, gr);
  const auto nf = static_cast<long>(mesh.num_faces());
  std::vector<double> err(mesh.num_faces(), 0.0);
  const std::vector<ClosestPointIndex::Hit> hits = index.closest_all(g.centroids);
#pragma omp parallel for schedule(static)
  for (long f = 0; f < nf; ++f) {
    const double c = std::min(1.0, std::abs(g.normals[f].dot(gr.normals[hits[f].face])));
    err[f] = std::acos(c) * 180.0 / kPi;
  }
  double sum = 0.0;
  for (double e : err) sum += e;
  return nf > 0 ? sum / static_cast<double>(nf) : 0.0;
}

double scanned_coverage(const Mesh& mesh, const Mesh& reference, const std::vector<Vec3>& scan, double radius) {
  FaceGeometry gr;
  compute_face_geometry(reference.positions, reference.faces, gr);
  const std::vector<double> to_scan = nearest_point_distances(scan, gr.centroids);
  ClosestPointIndex index(mesh);
  std::size_t seen = 0, covered = 0;
  for (std::size_t f = 0; f < reference.num_faces(); ++f) {
    if (!(to_scan[f] <= radius)) continue;
    ++seen;
    covered += index.closest(gr.centroids[f]).distance <= radius ? 1 : 0;
  }
  return seen > 0 ? static_cast<double>(covered) / static_cast<double>(seen) : 0.0;
}

void write_json(JsonWriter& w, const MeshMetrics& m, const ScanFit* fit) {
  const TopologyStats& t = m.topology;
  w.begin_object();
  w.key("topology").begin_object();
  w.field("vertices", t.vertices).field("faces", t.faces).field("edges", t.edges).field("boundary_edges", t.boundary_edges);
  w.field("boundary_loops", t.boundary_loops).field("nonmanifold_edges", t.nonmanifold_edges).field("components", t.components);
  w.field("isolated_vertices", t.isolated_vertices).field("degenerate_faces", t.degenerate_faces);
  w.field("inconsistent_edges", t.inconsistent_edges).field("nonfinite_vertices", t.nonfinite_vertices);
  w.end_object();
  w.field("bbox_diagonal", m.bbox_diagonal).field("mean_edge_length", m.mean_edge_length);
  w.field("quality_mean", m.quality_mean).field("quality_max", m.quality_max);
  if (m.has_reference) {
    w.key("reference").begin_object();
    w.key("msae_deg");
    m.same_connectivity ? w.value(m.msae_deg) : w.null();
    w.key("flipped_faces");
    m.same_connectivity ? w.value(m.flipped_faces) : w.null();
    w.field("ev", m.ev).field("ev_relative", m.ev_relative).field("distance_mean", m.distance_mean).field("distance_rms", m.distance_rms);
    w.field("hausdorff_to_reference", m.hausdorff_to_reference).field("hausdorff_from_reference", m.hausdorff_from_reference);
    w.field("hausdorff", m.hausdorff);
    w.key("volume_change");
    m.volume_change ? w.value(*m.volume_change) : w.null();
    w.end_object();
  }
  if (fit) {
    w.key("scan_fit");
    write_json(w, *fit);
  }
  w.end_object();
}

std::string metrics_json(const MeshMetrics& m, const ScanFit* fit) {
  JsonWriter w;
  write_json(w, m, fit);
  return w.str();
}

}  // namespace scanmesh
