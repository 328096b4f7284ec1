#pragma once
// Kokkos comes up once per process with the requested threads (OpenMP cannot be resized later).
#include <Kokkos_Core.hpp>
#include <sched.h>
#include <cstdlib>
#include "parallel/mpi_session.hpp"

namespace cgdem {

// The OpenMP binding a process gets unless the user set OMP_PROC_BIND. Pinned threads keep each particle
// range on one core, which pays when the process's threads fill the cores it may run on (threads <= 0:
// OpenMP's default, one per core). With fewer threads than cores it does harm: "spread" puts the first
// thread on the first core, so two single-threaded runs started side by side (a batch, two sweeps) share
// core 0 while core 1 idles. Under several MPI ranks mpirun places the processes, and pinning inside
// each would put every rank's first thread on the same core when the ranks are not bound.
inline const char* default_proc_bind(int threads, int cores, int ranks) {
  if (ranks > 1) return "false";
  return threads <= 0 || threads >= cores ? "spread" : "false";
}

// The cores this process may run on (its affinity mask: taskset, a cgroup's cpuset).
inline int usable_cores() {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
  const int n = CPU_COUNT(&set);
  return n > 0 ? n : 1;
}

struct KokkosSession {
  explicit KokkosSession(int threads) {
    setenv("OMP_PROC_BIND", default_proc_bind(threads, usable_cores(), parallel::world_size()), 0);
    setenv("OMP_PLACES", "threads", 0);
#if KOKKOS_VERSION >= 30700 // InitArguments gave way to InitializationSettings (removed in Kokkos 4)
    Kokkos::InitializationSettings init;
    if (threads > 0) init.set_num_threads(threads);
#else
    Kokkos::InitArguments init;
    if (threads > 0) init.num_threads = threads;
#endif
    Kokkos::initialize(init);
  }
  ~KokkosSession() {
    Kokkos::finalize();
  }
  KokkosSession(const KokkosSession&) = delete;
  KokkosSession& operator=(const KokkosSession&) = delete;
};

} // namespace cgdem
