#include "scanmesh/parallel.h"

#include <omp.h>

namespace scanmesh {

int thread_count() { return omp_get_max_threads(); }

void set_thread_count(int threads) { omp_set_num_threads(threads > 0 ? threads : omp_get_num_procs()); }

ThreadScope::ThreadScope(int threads) : previous_(omp_get_max_threads()) { set_thread_count(threads); }

ThreadScope::~ThreadScope() { omp_set_num_threads(previous_); }

}  // namespace scanmesh
