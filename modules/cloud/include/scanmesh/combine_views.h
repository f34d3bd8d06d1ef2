#pragma once
// Several views of one object into one cloud: merge_views concatenates views that are already in one frame
// (range scans posed by their .conf, clouds moved by a reader's `transform` or VIEWPOINT); register_views
// first refines rough poses with PCL's ICP, each view aligned to the views before it, coarse to fine:
// point-to-point at the coarse levels, then point-to-plane (or generalized ICP) at two point spacings.
// The options struct is the schema of the cloud.register stage.
#include <string>
#include <vector>

#include "scanmesh/length.h"
#include "scanmesh/point_cloud.h"
#include "scanmesh/schema.h"

namespace scanmesh {

/// One cloud of all finite points of the views (unorganized). Normals are kept where every view has them;
/// otherwise each point gets the unit direction towards its view's sensor (when known) as an unoriented
/// hint, which normal estimation uses to turn the normals outwards.
PointCloud merge_views(const std::vector<PointCloud>& views);

enum class RegisterMethod { point_to_plane, generalized };

struct RegisterOptions {
  RegisterMethod method = RegisterMethod::point_to_plane;
  Length max_distance = Length{10.0, Length::Unit::percent_of_diagonal};
  int iterations = 50;
  static const Schema<RegisterOptions>& schema() {
    static const Schema<RegisterOptions> s =
        Schema<RegisterOptions>()
            .choice("register_method", &RegisterOptions::method,
                    {{"point_to_plane", RegisterMethod::point_to_plane}, {"gicp", RegisterMethod::generalized}},
                    "ICP at the finest level (the coarser levels use point-to-point): point_to_plane: symmetric "
                    "point-to-plane (both views' tangent planes; the default); gicp: generalized ICP (plane to plane "
                    "covariances), slower.")
            .length("register_max_distance", &RegisterOptions::max_distance, open_closed(0, 1e300),
                    "Largest pose error to correct: the first correspondence distance, then a third of it at each level "
                    "down to two point spacings.")
            .integer("register_iterations", &RegisterOptions::iterations, closed(1, 1000), "count",
                     "ICP iterations at the finest level; each coarser level takes a tenth of them (at least 5).");
    return s;
  }
};

/// How one view was moved.
struct ViewAlignment {
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();  ///< applied to the view as it was read
  double rotation_deg = 0.0;   ///< angle of the correction's rotation
  double translation = 0.0;    ///< length of its translation, scene units
  double rms = 0.0;            ///< RMS distance of matched points afterwards, scene units
  double overlap = 0.0;        ///< share of the view's points matched within two spacings
  bool converged = false;
};

/// Aligns views[1..] one after another to the union of the views before them (views[0] stays), in place.
/// Throws InputError if a view has fewer than 10 finite points. Deterministic.
std::vector<ViewAlignment> register_views(std::vector<PointCloud>& views, const RegisterOptions& options);

}  // namespace scanmesh
