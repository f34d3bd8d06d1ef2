// scanmesh-full: every command (the scan stages over PCL, VTK and OpenCV included).
#include "cli.h"
#include "scanmesh/pipeline.h"

int main(int argc, char** argv) { return scanmesh::cli::main(argc, argv, &scanmesh::register_scan_stages); }
