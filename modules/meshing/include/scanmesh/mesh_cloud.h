#pragma once
// Cloud -> mesh with the method that suits the cloud. `auto` measures instead of guessing: organized frames
// and range grids get organized meshing; an unorganized cloud is meshed by greedy projection (which keeps
// the measured points as vertices) and, when that leaves points out or holes where the scan has data (a
// complete object, a sparse scan), by screened Poisson trimmed back to the data; the result that
// represents the points better is kept (measure_scan_fit). The options are the mesh.auto stage's schema.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "scanmesh/point_cloud.h"
#include "scanmesh/scan_fit.h"
#include "scanmesh/schema.h"
#include "scanmesh/triangulate.h"

namespace scanmesh {

enum class MeshMethod { automatic, gp3, organized, poisson };

/// The choice of method (mesh.auto and `scanmesh mesh`); each method's own options are its struct's.
struct MeshMethodOptions {
  MeshMethod method = MeshMethod::automatic;
  bool fill_holes = true;
  Length fill_trim = Length::spacings(1.5);
  Length fill_trim_one_sided = Length::spacings(3.0);
  static const Schema<MeshMethodOptions>& schema() {
    static const Schema<MeshMethodOptions> s = Schema<MeshMethodOptions>()
        .choice(
        "method", &MeshMethodOptions::method,
        {{"auto", MeshMethod::automatic}, {"gp3", MeshMethod::gp3}, {"organized", MeshMethod::organized}, {"poisson", MeshMethod::poisson}},
        "auto: organized meshing for grids; otherwise greedy projection, or screened Poisson where greedy projection "
        "leaves points out or holes (the better fit to the points wins); gp3 keeps the measured points as vertices; "
        "organized needs a grid cloud; poisson makes a smooth surface with new vertices.")
        .flag("fill_holes", &MeshMethodOptions::fill_holes,
              "auto: close greedy projection's holes and gaps before judging it; a patch stays only where it lies "
              "within fill_trim of the points, so a gap the scan saw nothing of stays open.")
        .length("fill_trim", &MeshMethodOptions::fill_trim, at_least(0),
                "auto: a patch closing a gap stays only where each of its faces' centres lies within this of an "
                "input point (farther out a membrane spans a region no view saw, off the real surface); a hole's "
                "patch (its loop encloses points left out: measured surface) within poisson_trim.")
        .length("fill_trim_one_sided", &MeshMethodOptions::fill_trim_one_sided, at_least(0),
                "auto: fill_trim for one-sided clouds (a single view, a relief: 90% of the normals in one "
                "hemisphere), whose holes inside the surface are mostly spots the view saw around (dark, shiny, "
                "grazing), where a membrane stays close to the surface.");
    return s;
  }
};

/// What meshing did and why (the sidecar's decision of the mesh stage).
struct MeshingDecision {
  MeshMethod method = MeshMethod::gp3;  ///< the method whose mesh was returned
  std::string reason;                   ///< one sentence with the measured numbers
  std::vector<std::pair<std::string, double>> numbers;
  ScanFit fit;                          ///< of the returned mesh, before clean-up (auto only)
};

/// "gp3", "organized", "poisson", "auto".
const char* method_name(MeshMethod method);

/// Triangulates `cloud` with the chosen method. Normals are estimated (default options) when a method
/// needs them and the cloud has none. With `auto` on an unorganized cloud the candidates are measured
/// after a default clean-up (clean_mesh), and the winner is returned cleaned. `note`, if given, hears a
/// line as each step of that starts and ends (with its seconds): on a large cloud they take minutes.
Mesh mesh_cloud(PointCloud& cloud, const MeshMethodOptions& method, const Gp3Options& gp3, const OrganizedOptions& organized,
                const PoissonOptions& poisson, const CloudScale& scale, MeshingDecision* decision = nullptr,
                const std::function<void(const std::string&)>& note = {});

}  // namespace scanmesh
