#pragma once
// `--auto`: denoising that chooses its parameters and its stopping point from the mesh itself.
//
// 1. Noise: a vertex's height over its one-ring plane varies slowly with curvature but jumps with noise;
//    the robust spread of those jumps estimates the noise (noise_analysis.h).
// 2. Noise-free tessellations (vertices exactly in their faces' planes) are left alone, and so are surfaces
//    smooth at the scale of their edges (neighbouring vertices agree on their heights over their one-rings).
// 3. Impulsive noise (many isolated outliers, jumps above 6x the median with calm neighbours) is
//    removed by moving only the outliers: vertices whose jump is above 4x the median and the largest in
//    their one-ring (outlier_peaks), and boundary vertices off their curves.
// 4. Otherwise a feature-keeping run starts (narrow kernel). If after `probe_iterations` its surface is
//    still full of soft creases (20-45 degrees; the features of machined parts are sharper), they are
//    noise it locked in: the mesh is smooth (organic) and is denoised from the start with a wide kernel.
//    So is a mesh whose nearly flat edges stopped growing since half the probe while still few (the
//    kernel has cut a curved surface into facets; a machined part's faces go on flattening).
//    Either run stops by the discrepancy principle, once the vertices have moved about as far as the noise
//    displaced them. The feature-keeping run then looks on (to 1.5-2x its iterations): if the displacement
//    has levelled off meanwhile (flat and developable faces keep improving while nothing more moves), it
//    runs all iterations, else it returns the target's iteration. It does not stop while its soft
//    creases are still falling fast (less than half of what they were at half the iterations): the
//    filter is still taking noise out there.
// 5. The result is checked (no more of the surface turned against the smoothed input than the input
//    itself has, by area; volume kept); the last iteration that passed is returned (the input if none).
// 6. Folds the run left (faces turned against the smoothed input and their own neighbours) are relaxed
//    locally (unfold_faces.h), unless the input was returned; kept only if they turn no more of the
//    surface than before. The smoothed input here has the faces the noise folded turned back to the
//    surface around them (fold_reference), so folds the run never touched count too.
// 7. The run's mean move along the normals is measured: removing noise moves vertices both ways alike, so
//    a surface that moved one way by more than half the noise shrank (or swelled): reported, not undone.
// Every constant here comes from AutoRules, fitted by leave-one-model-out cross-validation over the
// tuning corpus (bench/auto_cv.cpp, README "Choosing parameters automatically").
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "scanmesh/denoise.h"
#include "scanmesh/geometry.h"
#include "scanmesh/mesh.h"
#include "scanmesh/topology.h"
#include "scanmesh/unfold_faces.h"

namespace scanmesh {

/// The constants of --auto's decisions (see the header comment); defaults are the values fitted on the
/// whole corpus.
/// Which spread of the vertex height jumps (noise_analysis.h) the discrepancy targets multiply.
enum class NoiseStatistic { median, rms, trimmed_rms };

struct AutoRules {
  NoiseStatistic noise_statistic = NoiseStatistic::trimmed_rms;
  double impulsive_share = 0.011;  ///< share of isolated outliers above which noise counts as impulsive
  double outlier_jump = 4.0;       ///< impulsive mode: vertices whose jump exceeds this x the median move
  bool outlier_peaks = true;       ///< ...and is the largest in their one-ring (DenoiseOptions::outlier_peaks)
  int impulsive_iterations = 100;
  double impulsive_sigma = 0.7;  ///< kernel width of the impulsive mode
  double impulsive_lambda = 0.2;
  double sharp_sigma = 0.7;   ///< feature-keeping kernel width
  double sharp_lambda = 0.2;
  double smooth_sigma = 2.0;  ///< wide kernel for smooth shapes
  double smooth_lambda = 0.2;
  /// A mesh whose vertices are the scanned points (DenoiseOptions::vertices_are_points) gets the wide
  /// kernel's lambda times min(1, noise level / this)^2 (0 = not scaled). The fidelity term evens out
  /// triangles by moving vertices along and across the surface; on a scan's irregular triangulation under
  /// weak noise that moves them off the surface more than the noise had (sparse scans, noise 0.07 x mean
  /// edge: one iteration of the wide kernel 5.5 degrees from the clean mesh with lambda 0 against 9.5 with
  /// 0.2, the input 3.9), while under strong noise it is what keeps faces from folding (single views,
  /// noise 0.3: 20.6 degrees and 4x the flipped faces with lambda 0 for both kernels). The feature-keeping
  /// kernel keeps its lambda: the probe's crease shares were fitted with it, and lowered it sent the real
  /// Kinect pyramid scan to the wide kernel (8.43 -> 13.18 degrees). Fitted leave-one-model-out on 40 scan
  /// pairs (bench/scan_pairs.cpp: eight models, five scan settings; none in the corpus) among constant,
  /// linear and squared scalings: seven of eight folds took the squared one with 0.4, one 0.3; held back
  /// 10.65 -> 9.98 degrees mean, pairs worse than their input 5 -> 3 (docs/EXPERIMENTS.md, "The fidelity
  /// weight on scanned meshes"). Not for Poisson's meshes of scans, whose regular triangles it does not
  /// disturb: there the same scaling cost 1-11% of the normal error on five sparse virtual scans.
  double scanned_lambda_level = 0.4;
  int probe_iterations = 14;      ///< feature-keeping iterations before the smooth/sharp decision
  double soft_crease_min_deg = 20.0;  ///< a soft crease: adjacent faces differ by more than this...
  double soft_crease_max_deg = 45.0;  ///< ...and at most this (real features of parts are sharper)
  double crease_share = 0.020;        ///< share of soft creases at the probe above which the mesh is smooth...
  double crease_share_per_level = 0.05;  ///< ...plus this times the noise level (strong noise leaves more)
  /// Flattening (0 = off): at the probe, a feature-keeping run whose nearly flat edges (faces within
  /// flat_max_deg of each other) are fewer than flat_share_max of the edges and grew since half the probe
  /// by less than this x the noise level, while more than flat_min_bends of the edges bend by over
  /// soft_crease_min_deg (a surface without any creases is left to the feature-keeping run, which
  /// suits it), is on a curved surface: taken as smooth. The flat and developable faces of a
  /// machined part go on flattening; a curved surface under the narrow kernel stops once its facets have
  /// formed, however few soft creases they leave (dense organic meshes). The growth limit is 0.5 since the
  /// fit takes in the two dense smooth models of the shared data (the dragon and the Igea scan's 20k and
  /// 60k versions), which it was 0.35 without: every fold but Igea's takes 0.5 of 0.35-0.7 (Igea's 0.4;
  /// docs/EXPERIMENTS.md, "The dense scans in the fit").
  double flat_growth_per_level = 0.5;
  double flat_share_max = 0.45;
  double flat_min_bends = 0.001;
  /// ...and fewer than this share bend by over soft_crease_max_deg (a part with curved faces between
  /// sharp edges keeps its feature-keeping run). 1 = no limit.
  double flat_max_strong = 0.04;
  double flat_max_deg = 2.0;
  /// Below this share of soft creases at the first probe the part is clearly machined: no stopping rule,
  /// every iteration runs (flat faces keep improving long after the noise-sized displacement). 0 = off:
  /// the fit replaced it with plateau_growth (a share of creases depends on the mesh's resolution).
  double clear_sharp_share = 0.0;
  double sharp_target = 0.8;      ///< discrepancy target, x the robust noise estimate, feature-keeping run
  /// ...which does not end that run while its soft creases are still falling fast: below this share of
  /// their value at half the iterations (the filter is still taking noise out, as on a part whose
  /// slivers keep creases long after the noise-sized displacement). 0 = off.
  double crease_fall = 0.5;
  /// ...and applies only to runs whose nearly flat edges (within flat_max_deg) are at least this share at
  /// the probe (measured when the flattening rule is on; 0 = every run). A surface with few flat edges
  /// after the probe is curved or bumpy: its creases falling are its shape being rounded off, not noise
  /// going, and the run that follows them overshoots (held back on the corpus: 125 of 146 pairs better than
  /// the defaults against 122 with the continuation for every run).
  double crease_fall_min_flat = 0.3;
  /// When the feature-keeping run reaches its target at iteration t, it goes on to plateau_span x t; if its displacement
  /// grew by less than this share meanwhile, the surface has levelled off (flat and developable parts keep
  /// improving while nothing moves) and every iteration runs; otherwise iteration t is returned. 0 = off.
  double plateau_growth = 0.010;
  /// How far the plateau rule looks on: to this many times the target's iterations (rounded up).
  double plateau_span = 1.5;
  /// The flat floor: a feature-keeping run that reaches its target before flat_floor_iterations with at
  /// least this share of its edges nearly flat (within flat_max_deg) goes on to flat_floor_iterations
  /// (or, if the plateau rule finds its displacement levelled, to the cap). A mostly flat surface (a
  /// part's faces, a relief, a depth scan of a room, a dense gently curved scan) keeps improving well past
  /// the noise-sized displacement while the narrow kernel holds its edges; the corpus's organic shapes
  /// stay below 45% flat edges there. 0 = off. Held back on the corpus: 135 of 152 pairs better than the
  /// defaults against 131 without (docs/EXPERIMENTS.md, "The flat floor").
  double flat_floor_share = 0.6;
  int flat_floor_iterations = 30;
  /// ...unless its normal displacement grows by more than this share of what it was at the target on the
  /// way: then it ends at that iteration. Past the target a flat surface's filter evens its faces out while
  /// its vertices hardly move; fine relief under weak noise keeps moving as it is ground off. 0 = no limit.
  /// On the corpus it moves one pair, Kinect under Gaussian 0.1 (3.03 -> 2.71 degrees held back), so the
  /// fold without the Kinect pairs ties and 20 of 21 fits take 0.15 of 0.1-0.5; on the test-only Igea
  /// scan it keeps relief the floor ground off (3.42 -> 2.82; docs/EXPERIMENTS.md, "The flat floor's growth limit").
  double flat_floor_growth = 0.15;
  double smooth_target = 0.45;    ///< the same for the wide-kernel run...
  /// ...plus this times the noise level: under weak noise the shape's own smoothing soon adds as much
  /// displacement as the noise removed, so the wide kernel's best stop comes early there.
  double smooth_target_per_level = 0.75;
  /// From noise level smooth_floor_level up, the wide-kernel target is at least this share of the noise
  /// (0 = off): above weak noise its best stop sits near a constant share (0.73-0.83 on the corpus's
  /// organic pairs), which the level term alone reaches only under strong noise.
  double smooth_target_floor = 0.75;
  double smooth_floor_level = 0.15;  ///< noise level (x mean edge) from which smooth_target_floor applies
  /// The wide-kernel run does not stop at its target while its soft creases are still falling fast: below
  /// this share of their value at half the iterations (as crease_fall for the feature-keeping run; 0 =
  /// off). On a triangulation of scanned points (greedy projection of a noisy scan) the displacement
  /// creeps past the target while the normals keep improving for three to six times as many iterations.
  /// It applies only while the soft creases are above the share that makes the probe call a surface
  /// smooth (crease_share + crease_share_per_level x level: noise still locked in): a smooth surface's few
  /// remaining creases keep falling towards none however long the run smooths its shape away (the Igea
  /// scan decimated to 20k faces ran 100-200 iterations without that floor, 8.5 -> 12.5 degrees).
  /// Every fold took 0.6 of 0.5-0.8 (held back on the corpus's grids: mean 7.548 -> 7.544 degrees, 127
  /// -> 128 of 146 pairs better than the peer; docs/EXPERIMENTS.md, "The wide kernel's crease-fall continuation").
  double smooth_crease_fall = 0.6;
  /// That floor on a triangulation of scanned points (DenoiseOptions::vertices_are_points): this share of
  /// the edges instead (if lower; negative: the probe's limit, as on other meshes). The probe's limit came
  /// from a dense smooth mesh given noise (the Igea), whose last creases fall however long it is smoothed;
  /// on dense scans meshed by greedy projection the wide kernel's best iterations lie two to ten times past
  /// where it ends the run, while with no floor at all a scan of a machined part or of fine relief is
  /// smoothed away (the rocker-arm from 6 views ran 118 iterations). Every fold but one took 0.005 of
  /// 0-0.02 (leave-one-model-out over the main job's 19 virtual scans it changes: mean normal error 10.33 ->
  /// 8.74 degrees held back; docs/EXPERIMENTS.md, "The crease floor on scanned triangulations").
  double points_crease_floor = 0.005;
  /// On a triangulation of scanned points whose first wide iteration left more edges bent over
  /// soft_crease_max_deg than in the soft band (depth noise wider than the point spacing), the wide
  /// kernel's continuation also counts as falling fast when every bend over soft_crease_min_deg falls
  /// below smooth_crease_fall x its share at half the iterations. There the first iterations turn hard
  /// creases into soft ones, so the soft share hides the fall and the run stopped at its target with the
  /// surface still rough (an organized single view of spot under depth noise 0.5: 5 iterations, 27.4
  /// degrees from the model; with this rule 57, 8.3). On coarse scans under weaker noise the shape's own
  /// bends fall as it is smoothed, hence the condition (without it three sparse scan pairs ran on and
  /// lost). No constant of its own; not on meshes given noise, where the corpus's rules were fitted
  /// (docs/EXPERIMENTS.md, "Strong depth noise: every bend counts").
  bool points_bend_fall = true;
  /// ...and on such a mesh the wide run does not stop at its target either while more edges than the
  /// probe's crease limit (crease_share + crease_share_per_level x level) still bend over
  /// soft_crease_max_deg: under noise far wider than the spacing the bends fall by only 0.7 per doubling
  /// of the iterations early on, and the target came after 4 (organized views under noise 0.7: spot, the
  /// cow and the teapot 41.9 / 32.9 / 37.1 degrees from the model, now 29.7 / 16.5 / 20.6). The same
  /// limit the probe applies to soft creases; no constant of its own.
  bool points_hard_floor = true;
  int max_iterations = 200;
  double radius_factor = 3.0;
  /// Closed meshes: relative volume change at which the run stops. Off: rounding a noisy part's edges
  /// changes its volume by a few percent on the way to sharp edges again (measured on cubes).
  double max_volume_change = 1e9;
  /// The check allows max(input's turned share, this share) of the surface (by area) turned against the
  /// smoothed input.
  double turned_slack = 0.002;
  /// After an iteration has passed the check, this many failing ones in a row end the run (it keeps the
  /// last that passed); a run whose first this many iterations all failed ends too (it keeps its input:
  /// on the corpus's curves every run that passes at all passes by iteration 5, and a layered scan ran
  /// all 200 before). 0 = run on. On the corpus no run passed again after a failing iteration; the one
  /// run that went on (teapot, impulsive) spent 75 iterations after the one it kept.
  int check_patience = 10;
  /// A mesh whose height agreement (NoiseAnalysis::height_agreement) is at least this is left as it is:
  /// neighbouring vertices agree on their heights over their one-rings, as on a surface smooth at the
  /// scale of its edges, where the noise estimate reads curvature and denoising only takes shape away.
  /// Not for meshes made from scanned points (DenoiseOptions::scanned). 0 = off. A round value above every
  /// noisy mesh measured, not fitted: the corpus's 170 noisy pairs read at most 0.51, the 40 scan pairs
  /// 0.42, the main job's meshes of the real clouds 0.55; the clean spot, homer, rocker-arm, teapot,
  /// hemisphere and dragon 0.61-0.94 (their --auto results were 0.2-3.9 degrees from themselves;
  /// docs/EXPERIMENTS.md, "Shrinkage is reported; clean smooth meshes; dense scans in the fit").
  double clean_agreement = 0.6;
  /// A result whose mean normal move (AutoReport::mean_normal_move) is larger than this x the noise
  /// estimate, either way, is reported as having moved the whole surface (shrunk or swollen) rather than
  /// removed noise, which moves vertices both ways alike: a warning, the result is kept. Half the noise: a
  /// round value between the measurements below, not fitted. On the corpus (--auto, 170 pairs) the
  /// refined cylinder reads -0.47 to -1.64 x the noise (volume -0.8% to -1.6%; under Gaussian noise 0.1
  /// its distance to the clean surface doubles), every other model -0.29 to +0.04 (docs/EXPERIMENTS.md,
  /// the same section).
  double shift_warning = 0.5;
  /// ...and than this x the mean edge length: a shift of a hundredth of an edge does not show at the
  /// mesh's own resolution (a clean mesh's noise estimate is near 0, so any move is many times it: the
  /// clean open hemisphere, one iteration, 0.006 edges). The cylinder's pairs move 0.018-0.15 edges, every
  /// other corpus pair at most 0.0015.
  double shift_warning_edges = 0.01;
};

/// The iteration up to which the plateau rule looks on from a target reached at `target_it`.
inline int plateau_end(int target_it, double span) {
  return target_it + static_cast<int>(std::ceil((span - 1.0) * target_it - 1e-9));
}

/// The wide-kernel run's discrepancy target, as a multiple of the noise estimate, at noise level `level`.
inline double smooth_target_ratio(const AutoRules& r, double level) {
  const double t = r.smooth_target + r.smooth_target_per_level * level;
  return r.smooth_target_floor > 0.0 && level >= r.smooth_floor_level ? std::max(t, r.smooth_target_floor) : t;
}

/// What --auto measured and decided (printed by the command line, in the sidecar and the report).
struct AutoReport {
  double noise_level = 0.0;    ///< robust noise estimate / mean edge length
  double noise = 0.0;          ///< the same in mesh units (the discrepancy targets are multiples of it)
  double exact_plane_fraction = 0.0;
  double impulsive_share = 0.0;
  double height_agreement = 0.0;  ///< NoiseAnalysis::height_agreement of the input
  double crease_share = -1.0;  ///< at the probe (-1 if no probe ran)
  double flat_share = -1.0;    ///< nearly flat edges at the probe (-1 if not measured: rule off, or no probe ran)
  double flat_share_half = -1.0;  ///< the same at half the probe
  std::string mode;            ///< "untouched", "impulsive", "sharp" or "smooth"
  std::string reason;          ///< one line saying why
  DenoiseOptions options;      ///< what was run (explicit user values kept)
  DenoiseReport run;           ///< iterations, stop reason, timings of the final run
  int probe_iterations = 0;    ///< iterations spent on a probe that was discarded
  int levelled_at = 0;         ///< the feature-keeping run's target iteration, when its displacement levelled off after it (0: did not)
  /// The first iteration at which the final run had reached its target but went on because its soft
  /// creases were still falling fast (AutoRules::crease_fall, or smooth_crease_fall for the wide kernel's
  /// run; 0: never).
  int ran_past_target = 0;
  /// The target iteration of a feature-keeping run that went on to AutoRules::flat_floor_iterations
  /// because its surface was mostly flat there (0: did not)...
  int flat_floor_from = 0;
  /// ...and the iteration it went on to (earlier than AutoRules::flat_floor_iterations where its
  /// displacement grew past AutoRules::flat_floor_growth, or where the result check ended the run).
  int flat_floor_to = 0;
  std::string check;           ///< outcome of the result check
  /// Area-weighted mean of the vertices' signed moves along the result's vertex normals (mesh units;
  /// mean_normal_move in denoise.h): near 0 when noise was removed, negative when the surface shrank
  /// (normals facing out).
  double mean_normal_move = 0.0;
  /// Relative change of the enclosed volume (closed meshes; 0 otherwise).
  double volume_change = 0.0;
  /// |mean_normal_move| above AutoRules::shift_warning x the noise (and shift_warning_edges x the mean
  /// edge): the run moved the surface as a whole.
  bool shifted = false;
  UnfoldReport unfold;         ///< folds found after the run and left after unfolding (step 6)
};

/// Share of the manifold edges whose two faces' normals differ by an angle in (min_deg, max_deg]
/// (min_deg < 0: [0, max_deg]). Soft creases are (20, 45]; nearly flat edges [0, 2].
double bend_share(const FaceGeometry& geometry, const Topology& topology, double min_deg, double max_deg);

/// What the result check measures: the share of the surface (by area) whose faces point against the
/// reference normals (`prefiltered_normals(mesh, 3, 2, 4)` of the input). Slivers, whose normals are
/// noise, weigh nothing; a turned patch of real surface weighs its size.
double turned_area_share(const FaceGeometry& geometry, const std::vector<Vec3>& reference);

/// Denoises `mesh` in place with parameters chosen from the mesh. Fields of `given` named in
/// `explicit_fields` (schema names, e.g. "sigma_s", "iterations") are kept as given; the others are
/// chosen. Deterministic and independent of the thread count.
AutoReport denoise_auto(Mesh& mesh, const DenoiseOptions& given, const std::vector<std::string>& explicit_fields = {},
                        const AutoRules& rules = {}, const ProgressCallback& progress = {});

}  // namespace scanmesh
