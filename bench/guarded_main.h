#pragma once
// A bench program's main: its errors (a missing file, a wrong folder) end it with a message and status 1
// instead of an abort on an uncaught exception.
#include <cstdio>
#include <exception>

namespace scanmesh::bench {

inline int guarded_main(int (*run)(int, char**), int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}

}  // namespace scanmesh::bench
