// scanmesh: denoise, noise and eval without loading PCL, VTK or OpenCV; other commands run scanmesh-full.
#include "cli.h"

int main(int argc, char** argv) { return scanmesh::cli::main(argc, argv, nullptr); }
