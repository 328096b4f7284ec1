#pragma once
// Kokkos comes up once per process with the requested threads (OpenMP cannot be resized later).
#include <Kokkos_Core.hpp>
#include <cstdlib>
#include "parallel/mpi_session.hpp"

namespace cgdem {

struct KokkosSession {
  explicit KokkosSession(int threads) {
    // Pinned threads keep each particle range on one core (and quiet Kokkos' warning); users may override.
    // Under several MPI ranks mpirun places the processes: pinning inside each would put every rank's
    // first thread on the same core when the ranks are not bound (--bind-to none, oversubscribed).
    setenv("OMP_PROC_BIND", parallel::world_size() > 1 ? "false" : "spread", 0);
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
