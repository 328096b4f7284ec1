#pragma once
// Instantiates Simulation<Law, ExecSpace> for every backend this Kokkos build has. Included only by the
// drivers/physics_*.cpp translation units, one compiled contact law each (compile time stays bounded
// and parallel).
#include <stdexcept>
#include "kernels/simulation.hpp"

namespace cgdem {

template <class Law>
std::unique_ptr<Engine> make_simulation(const EngineConfig& config, const std::string& physics,
                                        const std::string& backend) {
#if defined(KOKKOS_ENABLE_OPENMP)
  if (backend == "openmp") return std::make_unique<kernels::Simulation<Law, Kokkos::OpenMP>>(config, physics, backend);
#endif
#if defined(KOKKOS_ENABLE_SERIAL)
  if (backend == "serial") return std::make_unique<kernels::Simulation<Law, Kokkos::Serial>>(config, physics, backend);
#endif
#if defined(KOKKOS_ENABLE_CUDA)
  if (backend == "cuda") return std::make_unique<kernels::Simulation<Law, Kokkos::Cuda>>(config, physics, backend);
#endif
  throw std::invalid_argument("backend '" + backend + "' is not compiled into this Kokkos build");
}

} // namespace cgdem

// One compiled law: defines the factory the registry (drivers/physics_registry.cpp) lists under `fn`.
#define CGDEM_DEFINE_PHYSICS(fn, ...)                                                                      \
  namespace cgdem {                                                                                       \
  std::unique_ptr<Engine> fn(const EngineConfig& config, const std::string& physics,                     \
                             const std::string& backend) {                                               \
    return make_simulation<__VA_ARGS__>(config, physics, backend);                                        \
  }                                                                                                       \
  }
