#pragma once
// Folds left by denoising, undone locally (beyond the paper; --auto's last step). A face the run turned
// against the smoothed input, and against its own unturned neighbours, is a fold: a vertex pulled across
// its neighbour's edge, most often an impulsive outlier left half-way or a small facet a feature-keeping
// run snapped to the wrong side. Its corners are relaxed within the surface, towards the middle of their
// neighbours, a step at a time, each move kept only if it turns fewer faces around that vertex than
// before, or as many and leaves them leaning less from the reference (area x (1 - cos)). Faces that were slivers in the input are left as they are: their normals are noise, and moving
// their corners bends the large faces next to them (measured on a CAD tessellation with zipper strips).
#include <cstddef>
#include <vector>

#include "scanmesh/geometry.h"
#include "scanmesh/mesh.h"
#include "scanmesh/topology.h"

namespace scanmesh {

struct UnfoldReport {
  std::size_t folds = 0;      ///< folded faces found before the first step
  std::size_t remaining = 0;  ///< folded faces left after the last
  std::size_t moved = 0;      ///< vertex moves made (a vertex may move in several rounds)
};

/// `reference` with the faces that point against their surroundings turned back: a face whose reference
/// points against those of at least two of its edge neighbours and lies more than ~127 degrees from the
/// area-weighted sum of the references of the faces around its corners (`areas` per face) takes that
/// sum's direction. A face the noise folded over (a vertex pulled across its neighbour's edge) keeps its
/// own normal through the robust prefilter, whose Tukey weight gives a neighbour 180 degrees away
/// nothing; against the raw reference such a fold looks right and its repair turned. Deterministic (each
/// face reads the unrepaired references only). `topology` needs face_faces.
std::vector<Vec3> fold_reference(const std::vector<Vec3>& reference, const std::vector<Face>& faces, const Topology& topology,
                                 const std::vector<double>& areas);

/// Unfolds `positions` (the denoised mesh; `faces` and `topology` are its connectivity) in place.
/// `input` holds the positions before denoising (for the sliver test) and `reference` one unit normal per
/// face that the faces should not point against (--auto: prefiltered_normals of the input). At most
/// `rounds` rounds; each moves every corner of a folded face by `step` x its distance to the mean of its
/// neighbours (a boundary vertex: of its two boundary neighbours), without the component along its
/// faces' reference normal. Deterministic, one thread; the work is proportional to the folds' stars.
/// `input_slivers`: whether faces that were slivers in the input are unfolded too (false: they are left as
/// they are, as on a CAD tessellation, whose slivers' normals are noise; true for a triangulation of
/// scanned points, whose slivers are the triangulation's and whose folds are real defects).
UnfoldReport unfold_faces(std::vector<Vec3>& positions, const std::vector<Face>& faces, const Topology& topology,
                          const std::vector<Vec3>& input, const std::vector<Vec3>& reference, int rounds = 10, double step = 0.5,
                          bool input_slivers = false);

}  // namespace scanmesh
