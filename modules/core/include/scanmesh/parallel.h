#pragma once
// Thread-count control. Every parallel loop in scanmesh writes only its own output slots or reduces in a
// fixed order, so results are bit-identical for any thread count.

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

}  // namespace scanmesh
