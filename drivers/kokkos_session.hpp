#pragma once
// Kokkos comes up once per process with the requested threads (OpenMP cannot be resized later).
#include <Kokkos_Core.hpp>
#include <cstdlib>

namespace cgdem {

struct KokkosSession {
  explicit KokkosSession(int threads) {
    // Pinned threads keep each particle range on one core (and quiet Kokkos' warning); users may override.
    setenv("OMP_PROC_BIND", "spread", 0);
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
