#pragma once
// Handing freed memory back to the operating system.

namespace scanmesh {

/// Returns the allocator's free pages to the system (glibc: malloc_trim; elsewhere nothing). Many small
/// blocks freed after a large step (the k-d tree's result rows, per-row vectors) otherwise stay in the
/// process and count towards its peak for the rest of the run. Costs a walk over the heap: call it after a
/// step, not inside a loop.
void return_free_memory();

}  // namespace scanmesh
