#pragma once
// The virtual scanner's settings on the command line of the bench tools that make scans
// (`--views N`, `--pixels WxH`, `--scan-noise S`, `--dropouts N`, `--dropout-radius R`), read the same way by each.
#include <cstring>
#include <stdexcept>
#include <string>

#include "scanmesh/virtual_scan.h"

namespace scanmesh::bench {

/// If argv[i] is one of the scanner's options, reads it (and its value, advancing i) into `options` and
/// returns true. Throws std::invalid_argument on a malformed value.
inline bool read_scan_option(int& i, int argc, char** argv, VirtualScanOptions& options) {
  if (i + 1 >= argc) return false;
  if (!std::strcmp(argv[i], "--views")) {
    options.views = std::stoi(argv[++i]);
  } else if (!std::strcmp(argv[i], "--dropouts")) {
    options.dropouts = std::stoi(argv[++i]);
  } else if (!std::strcmp(argv[i], "--dropout-radius")) {
    options.dropout_radius = std::stod(argv[++i]);
  } else if (!std::strcmp(argv[i], "--scan-noise")) {
    options.noise = std::stod(argv[++i]);
  } else if (!std::strcmp(argv[i], "--pixels")) {
    const std::string wh = argv[++i];
    const auto x = wh.find('x');
    if (x == std::string::npos) throw std::invalid_argument("--pixels takes WIDTHxHEIGHT, e.g. 96x72, not '" + wh + "'");
    options.width = std::stoi(wh.substr(0, x));
    options.height = std::stoi(wh.substr(x + 1));
  } else {
    return false;
  }
  return true;
}

}  // namespace scanmesh::bench
