#pragma once
// The command-line tool's entry point, shared by its two executables (see cli.cpp).
namespace scanmesh::cli {

/// Runs one command. `add_scan_stages` is register_scan_stages (pipeline.h) in the executable that links
/// the scan stages (PCL, VTK, OpenCV), null in the light one.
int main(int argc, char** argv, void (*add_scan_stages)());

}  // namespace scanmesh::cli
