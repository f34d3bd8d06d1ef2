#pragma once
// Handing freed memory back to the operating system, and asking for huge pages.
#include <cstddef>

namespace scanmesh {

/// Returns the allocator's free pages to the system (glibc: malloc_trim; elsewhere nothing). Many small
/// blocks freed after a large step (the k-d tree's result rows, per-row vectors) otherwise stay in the
/// process and count towards its peak for the rest of the run. Less than 8 MiB of free memory is kept
/// for the next step. Costs a walk over the heap: call it after a step, not inside a loop.
void return_free_memory();

/// Asks the system to back [p, p + bytes) with huge pages where it can (Linux: madvise MADV_HUGEPAGE on
/// the whole 2 MiB pages inside; elsewhere nothing). For large arrays read at random, before they are
/// first written: a table of tens of megabytes in 4 KiB pages costs a TLB miss on most reads. The CLI
/// has glibc do this for every large block; a program that embeds the library gets it here for the
/// filter's records (1.3M faces in generation order, one thread: 194 -> 81 ms per pass).
void advise_huge_pages(void* p, std::size_t bytes);

/// Frees a container's memory now (clear() keeps the capacity): for tables a step no longer reads while
/// later steps allocate theirs.
template <class T>
void release(T& container) {
  container = T{};  // move-assigning an empty one hands its storage back
}

}  // namespace scanmesh
