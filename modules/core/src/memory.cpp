#include "scanmesh/memory.h"

#include <cstdlib>  // defines __GLIBC__ on glibc

#include <cstdint>

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace scanmesh {

constexpr std::size_t kKeepFree = std::size_t{8} << 20;

void return_free_memory() {
#if defined(__GLIBC__)
  // Below kKeepFree the pages stay: a small mesh's next step reuses them, where fresh pages would cost a
  // page fault each (10 us on this project's VM: a third of a 13k-face mesh's set-up).
  if (mallinfo2().fordblks < kKeepFree) return;
  malloc_trim(0);
#endif
}

void advise_huge_pages(void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
  const auto begin = (reinterpret_cast<std::uintptr_t>(p) + kHuge - 1) & ~(kHuge - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(p) + bytes) & ~(kHuge - 1);
  if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);  // a hint: failure is harmless
#else
  (void)p;
  (void)bytes;
#endif
}

}  // namespace scanmesh
