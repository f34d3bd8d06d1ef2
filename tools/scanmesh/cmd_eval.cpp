#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include "cli_common.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/errors.h"
#include "scanmesh/evaluate.h"
#include "scanmesh/cloud_io.h"
#include "scanmesh/mesh_io.h"
#include "scanmesh/neighbourhoods.h"
#include "scanmesh/scan_fit.h"

namespace scanmesh::cli {

int run_eval(const std::vector<std::string>& args) {
  po::options_description o("options");
  o.add_options()
    ("reference,r", po::value<std::string>(),
     "ground-truth mesh (MSAE and flips need the same faces as MESH), or the point cloud MESH was made from "
     "(any cloud format): distances from its points to the mesh, coverage, holes and pieces")
    ("json", po::value<std::string>(), "also write the metrics as JSON to this file")
    ("quiet,q", po::bool_switch(), "print nothing but errors (use with --json)");
  po::variables_map vm;
  if (!parse(args, o, {"MESH"}, vm, "scanmesh eval MESH [--reference REF] [--json FILE]",
             "Measures a mesh: triangle quality Q (circumradius / shortest edge; 0.577 is equilateral) and topology;\n"
             "with a reference also MSAE (mean face-normal angle error, degrees), flipped faces (> 90 degrees),\n"
             "E_v (area-weighted RMS distance of the vertices to the reference surface, absolute and relative to\n"
             "the reference's bounding-box diagonal), Hausdorff distance both ways (at vertices) and the volume\n"
             "change of closed meshes."))
    return kOk;
  const std::string path = vm["MESH"].as<std::string>();
  const bool quiet = vm["quiet"].as<bool>();
  if (vm.count("json")) {
    const std::string json = vm["json"].as<std::string>();
    if (json == path || same_file(json, path) || (vm.count("reference") && same_file(json, vm["reference"].as<std::string>())))
      throw UsageError("--json '" + json + "' would overwrite an input");
  }
  std::vector<std::string> warnings;
  const Mesh mesh = read_mesh(path, &warnings);
  std::unique_ptr<Mesh> reference;
  std::unique_ptr<PointCloud> cloud;
  if (vm.count("reference")) {
    const std::string ref = vm["reference"].as<std::string>();
    if (holds_cloud(ref)) cloud = std::make_unique<PointCloud>(read_cloud(ref, &warnings));
    else reference = std::make_unique<Mesh>(read_mesh(ref, &warnings));
  }
  if (cloud)  // copies of a point make every neighbour search around it quadratic (as on reading in a pipeline)
    if (const std::size_t copies = merge_copies(*cloud); copies > 0)
      warnings.push_back(vm["reference"].as<std::string>() + ": " + std::to_string(copies) +
                         (cloud->organized() ? " pixels at shared positions left out" : " copies of points merged"));
  print_warnings(warnings, quiet);
  if (reference && reference->num_faces() != mesh.num_faces() && !quiet)
    std::cerr << "warning: the reference has " << reference->num_faces() << " faces and the mesh " << mesh.num_faces()
              << "; MSAE and flips need the same faces and are not reported\n";
  const MeshMetrics m = evaluate(mesh, reference.get());
  std::optional<ScanFit> fit;
  if (cloud) fit = measure_scan_fit(mesh, cloud->points, measure_scale(*cloud).spacing);
  if (!quiet) {
    const auto& t = m.topology;
    std::printf("mesh:       %s\n", path.c_str());
    std::printf("topology:   %zu vertices, %zu faces, %zu edges, %zu boundary loops, %zu non-manifold edges, %zu components\n",
                t.vertices, t.faces, t.edges, t.boundary_loops, t.nonmanifold_edges, t.components);
    std::printf("defects:    %zu degenerate faces, %zu inconsistently oriented edges, %zu non-finite vertices, %zu isolated vertices\n",
                t.degenerate_faces, t.inconsistent_edges, t.nonfinite_vertices, t.isolated_vertices);
    if (m.has_reference && t.isolated_vertices > 0)
      std::printf("            (isolated vertices count in the distances to the reference: they lie on no face)\n");
    const auto no_q = static_cast<std::size_t>(
        std::count_if(m.face_quality.begin(), m.face_quality.end(), [](double q) { return !std::isfinite(q); }));
    if (no_q == m.face_quality.size()) {
      std::printf("Q:          none: no face has a finite Q (all degenerate or beyond double range)\n");
    } else {
      std::printf("Q:          %.4f mean, %.4f max (0.577 = equilateral)", m.quality_mean, m.quality_max);
      if (no_q > 0)
        std::printf(" over %zu faces; %zu without a finite Q (degenerate or beyond double range) left out", m.face_quality.size() - no_q, no_q);
      std::printf("\n");
    }
    if (m.has_reference) {
      if (m.same_connectivity) {
        std::printf("MSAE:       %.4f deg\n", m.msae_deg);
        std::printf("flips:      %zu faces > 90 deg\n", m.flipped_faces);
      }
      std::printf("E_v:        %.6g (%.4e x bbox diagonal)\n", m.ev, m.ev_relative);
      std::printf("Hausdorff:  %.6g (to reference %.6g, from reference %.6g)\n", m.hausdorff, m.hausdorff_to_reference,
                  m.hausdorff_from_reference);
      if (m.volume_change) std::printf("volume:     %+.4f%% change\n", 100.0 * *m.volume_change);
    }
    if (fit) {
      std::printf("cloud:      %zu points, mean spacing %.6g\n", fit->points, fit->spacing);
      std::printf("coverage:   %.2f%% of the points within %.6g (%s) of the mesh (%zu left out)\n", 100.0 * fit->coverage,
                  fit->coverage_radius, coverage_radius_words(*fit).c_str(), fit->points_left_out);
      std::printf("scatter:    %.6g across the surface (the points' noise, scene units)\n", fit->scatter);
      std::printf("distance:   points to mesh: mean %.6g, 95th percentile %.6g, max %.6g\n", fit->distance_mean, fit->distance_p95,
                  fit->distance_max);
      std::printf("loops:      %zu rims, %zu holes (largest %.4g around), %zu gaps in the data; %zu pieces (main %.1f%% of faces)\n",
                  fit->rims, fit->holes, fit->largest_hole, fit->gaps, fit->pieces, 100.0 * fit->main_piece_share);
      if (fit->layered_pieces > 0)
        std::printf("layers:     %zu pieces (%.1f%% of the faces) lie over another piece\n", fit->layered_pieces, 100.0 * fit->layered_share);
      for (const auto& p : scan_fit_problems(*fit)) std::printf("problem:    %s\n", p.c_str());
    }
  }
  if (vm.count("json")) write_file_atomically(vm["json"].as<std::string>(), metrics_json(m, fit ? &*fit : nullptr));
  return kOk;
}

}  // namespace scanmesh::cli
