#include "grid_curves.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace scanmesh::bench {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  std::string tok;
  while (std::getline(in, tok, ',')) out.push_back(tok);
  return out;
}

}  // namespace

std::string curve_key(double sigma, double lambda, double radius, double outlier) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f/%.2f/%.1f/%.0f", sigma, lambda, radius, outlier);
  return buf;
}

std::map<std::string, PairData> load_grids(const std::vector<std::string>& files) {
  std::map<std::string, PairData> pairs;
  for (const auto& file : files) {
    std::ifstream in(file);
    if (!in) {
      std::fprintf(stderr, "cannot read %s\n", file.c_str());
      std::exit(1);
    }
    std::string line;
    while (std::getline(in, line)) {
      const auto f = split(line);
      if (f.size() >= 15 && f[0] == "P") {
        PairData& p = pairs[f[1] + "|" + f[2]];
        p.model = f[1];
        p.variant = f[2];
        p.faces = std::stol(f[4]);
        p.noisy_msae = std::stod(f[5]);
        p.noisy_flips = std::stol(f[6]);
        p.level = std::stod(f[7]);
        p.isolated = std::stod(f[8]);
        p.plane = std::stod(f[9]);
        p.edge = std::stod(f[10]);
        p.jmed = std::stod(f[11]);
        p.jrms = std::stod(f[13]);
        p.jtrim = std::stod(f[14]);
      } else if (f.size() >= 20 && f[0] == "C") {
        PairData& p = pairs[f[1] + "|" + f[2]];
        Checkpoint c;
        c.it = std::stoi(f[8]);
        c.msae = std::stod(f[9]);
        c.flips = std::stol(f[10]);
        c.ndisp = std::stod(f[11]);
        c.s20 = std::stod(f[14]);
        c.s45 = std::stod(f[16]);
        c.turned = std::stol(f[18]);
        p.input_turned = std::stol(f[19]);
        if (f.size() >= 22) c.turned_area = std::stod(f[20]), p.input_turned_area = std::stod(f[21]);
        if (f.size() >= 23) c.flat = std::stod(f[22]);
        p.curves[curve_key(std::stod(f[3]), std::stod(f[4]), std::stod(f[5]), -std::stod(f[13]))].push_back(c);
      }
    }
  }
  return pairs;
}

}  // namespace scanmesh::bench
