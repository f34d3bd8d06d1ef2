#pragma once
// Thread-count control. Every parallel loop in scanmesh writes only its own output slots or reduces in a
// fixed order, so results are bit-identical for any thread count.

namespace scanmesh {

/// Number of threads parallel loops use now.
int thread_count();

/// Sets the thread count for the rest of the process; 0 means "all cores".
void set_thread_count(int threads);

}  // namespace scanmesh
