#pragma once
// The tuning corpus for --auto: clean models from ../shared/data (train/, the clean halves of pairs/, and
// a few of meshes/), each made into seeded noisy pairs with the noise stage (the library call behind
// `scanmesh noise`), plus the real noisy halves of pairs/. Benches that fit or check --auto share it, so
// every one of them sees the same pairs, grouped by model for leave-one-model-out cross-validation.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "scanmesh/add_noise.h"
#include "scanmesh/mesh.h"

namespace scanmesh::bench {

/// One clean/noisy pair with the same vertex order and faces.
struct Pair {
  std::string model;    ///< cross-validation group: pairs of one model are held back together
  std::string variant;  ///< e.g. "gaussian-random-0.2" or "given" for a pair shipped with the data
  std::string kind;     ///< "organic" or "mechanical", from SOURCES.md (for reading tables only)
  Mesh clean, noisy;
};

/// A model of the corpus before noise is added.
struct Model {
  std::string name, kind;
  std::filesystem::path clean;  ///< clean mesh file
  std::vector<std::filesystem::path> given;  ///< noisy files shipped with it (same vertices and faces)
  /// Loop subdivision steps applied to the clean mesh: a dense, smooth version of a coarse model (4x the
  /// faces per step), like the dense scans users bring.
  int subdivisions = 0;
  /// Cross-validation group (Pair::model): a dense version is held back with its coarse original.
  std::string group;
  /// Made in code instead of read from `clean` (test::make_zippered_cylinder, tests/helpers.h).
  bool generated = false;
  /// Quadric decimation (VTK) of the clean mesh to about this many faces (0: none): a coarser version of
  /// a dense model, at the resolution of the organic meshes users denoise most (17k-124k faces).
  std::size_t decimate_to = 0;
};

/// One step of Loop subdivision (Loop 1987): every triangle into four, new edge points 3/8 + 3/8 + 1/8 +
/// 1/8 of the edge's ends and opposite corners, old vertices moved by Warren's weights; on boundaries
/// the cubic B-spline rules (edge midpoints, 3/4 + 1/8 + 1/8). Non-manifold edges are split at their
/// midpoints.
Mesh loop_subdivide(const Mesh& mesh);

/// VTK's quadric decimation (Garland and Heckbert 1997) to about `faces` triangles; deterministic.
Mesh decimate(const Mesh& mesh, std::size_t faces);

/// The noisy variants made from every clean model: (kind, direction, level x mean edge).
struct Variant {
  NoiseKind kind;
  NoiseDirection direction;
  double level;
  [[nodiscard]] std::string name() const;
};
const std::vector<Variant>& corpus_variants();

/// The models found under `data` (../shared/data); empty if the folder is absent.
std::vector<Model> corpus_models(const std::filesystem::path& data);
/// Whether `list` (comma-separated names, e.g. "spot,igea-tristrips") names the model or its
/// cross-validation group (so a group's name selects its dense or coarse versions too).
bool listed(const Model& model, const std::string& list);

/// The models a corpus bench called as `NAME [DATA_DIR] [--only MODEL]` works on (default ../shared/data;
/// with --only, that model alone). Nothing, after printing "skipped: ... not found", when the folder is
/// absent, so the bench ends cleanly without the shared data. `--mesh FILE` (repeatable) takes that clean
/// mesh instead of the corpus: a model no rule was fitted on, with the corpus's noise variants.
std::optional<std::vector<Model>> corpus_models_from_args(int argc, char** argv);

/// The numbers of a command-line list "a,b,c".
std::vector<double> parse_list(const char* s);

/// Loads the pairs of one model: the given pair (if any) and every variant of corpus_variants(), seeded by
/// the model name and the variant so the corpus is the same on every machine.
std::vector<Pair> load_pairs(const Model& model);

}  // namespace scanmesh::bench
