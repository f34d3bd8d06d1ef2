#pragma once
// Thread-count control. Every parallel loop in scanmesh writes only its own output slots or reduces in a
// fixed order, so results are bit-identical for any thread count.

#include <algorithm>
#include <vector>

namespace scanmesh {

/// Number of threads parallel loops use now.
int thread_count();

/// Sets the thread count for the rest of the process; 0 means "all cores".
void set_thread_count(int threads);

/// The thread count of the calling thread's parallel loops while it lives (0 = all cores), the previous
/// count restored afterwards: how a caller passes `threads` to a library call without changing the
/// process's state. OpenMP keeps the count per calling thread, so callers on different threads do not
/// disturb each other.
class ThreadScope {
 public:
  explicit ThreadScope(int threads);
  ~ThreadScope();
  ThreadScope(const ThreadScope&) = delete;
  ThreadScope& operator=(const ThreadScope&) = delete;

 private:
  int previous_;
};

/// The sum of term(i) over i in [0, n), the same bits for any thread count: blocks of 1024 terms are
/// summed in parallel, each in order, and the block sums are added in order. T: double or an Eigen vector.
template <class T, class Term>
T ordered_sum(long n, const T& zero, const Term& term) {
  constexpr long kBlock = 1024;
  const long blocks = n > 0 ? (n + kBlock - 1) / kBlock : 0;
  std::vector<T> part(static_cast<std::size_t>(blocks), zero);
#pragma omp parallel for schedule(static) if (blocks > 1)
  for (long b = 0; b < blocks; ++b) {
    T s = zero;
    for (long i = b * kBlock, end = std::min(n, (b + 1) * kBlock); i < end; ++i) s += term(i);
    part[static_cast<std::size_t>(b)] = s;
  }
  T total = zero;
  for (const T& s : part) total += s;
  return total;
}

}  // namespace scanmesh
