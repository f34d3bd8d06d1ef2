#pragma once
// The quality curves scanmesh_auto_grid writes (CSV: a P line per pair, C lines per checkpoint), read back
// for scanmesh_auto_cv's leave-one-model-out fits.
#include <map>
#include <string>
#include <vector>

namespace scanmesh::bench {

struct Checkpoint {
  int it = 0;
  double msae = 0.0, ndisp = 0.0, s20 = 0.0, s45 = 0.0;
  long flips = 0, turned = 0;
  double turned_area = -1.0;  ///< share of the area turned against the smoothed input, as --auto's check (-1: not in the file)
  double flat = -1.0;  ///< share of nearly flat edges (AutoRules::flat_max_deg), for the flattening rule (-1: not in the file)
};

struct PairData {
  std::string model, variant;
  long faces = 0;
  double noisy_msae = 0.0;
  long noisy_flips = 0;
  double level = 0.0, isolated = 0.0, plane = 0.0, edge = 0.0, jmed = 0.0, jrms = 0.0, jtrim = 0.0;
  long input_turned = 0;
  double input_turned_area = -1.0;
  std::map<std::string, std::vector<Checkpoint>> curves;  // "sigma/lambda/radius/outlier"
};

/// "0.70/0.20/3.0/0": the key of a candidate setting's curve.
std::string curve_key(double sigma, double lambda, double radius, double outlier);

/// Every pair of the grid files, keyed "model|variant"; exits with a message if a file cannot be read.
std::map<std::string, PairData> load_grids(const std::vector<std::string>& files);

}  // namespace scanmesh::bench
