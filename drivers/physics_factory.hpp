#pragma once
// Instantiates Simulation<Law, ExecSpace> for every backend this Kokkos build has, for the laws of one
// translation unit (drivers/physics_*.cpp: one normal law or one direct scaling method each, so compile
// time stays bounded and parallel). The registry (drivers/physics_registry.cpp) collects their entries.
#include <stdexcept>
#include <string>
#include <vector>
#include "drivers/physics_registry.hpp"
#include "kernels/simulation.hpp"
#include "models/component_lists.hpp"
#include "models/scaling/direct_force_scaling.hpp"

namespace cgdem {

template <class Law>
std::unique_ptr<Engine> make_simulation(const EngineConfig& config, const std::string& physics,
                                        const std::string& backend) {
#if defined(KOKKOS_ENABLE_OPENMP)
  if (backend == "openmp")
    return std::make_unique<kernels::Simulation<Law, Kokkos::OpenMP>>(config, physics, backend);
#endif
#if defined(KOKKOS_ENABLE_SERIAL)
  if (backend == "serial")
    return std::make_unique<kernels::Simulation<Law, Kokkos::Serial>>(config, physics, backend);
#endif
#if defined(KOKKOS_ENABLE_CUDA)
  if (backend == "cuda")
    return std::make_unique<kernels::Simulation<Law, Kokkos::Cuda>>(config, physics, backend);
#endif
  throw std::invalid_argument("backend '" + backend + "' is not compiled into this Kokkos build");
}

// Every combination of the component lists with `Normal` that makes physical sense.
template <class Normal>
void add_laws_of(std::vector<PhysicsEntry>& registry) {
  models::for_each_sensible_law<Normal>([&](auto law, std::string name) {
    registry.push_back({std::move(name), &make_simulation<typename std::decay_t<decltype(law)>::type>});
  });
}

// The I-th normal law's combinations (drivers/physics_normal_<I>.cpp instantiates it).
template <int I>
void add_normal_laws(std::vector<PhysicsEntry>& registry) {
  if constexpr (I < models::list_size(models::NormalLaws{}))
    add_laws_of<models::TypeAt<I, models::NormalLaws>>(registry);
}

// The laws of Hu et al. 2022's validation, which direct force scaling wraps: Hertz-Mindlin, JKR-Mindlin
// and Hertz with capillary bridges, frictionless (the compression studies) and with Mindlin friction (the
// vertical mixer, Table 6: sliding friction 0.3).
using DirectlyScaledLaws = models::TypeList<
    models::ContactLaw<models::HertzTsuji, models::NoAdhesion, models::MindlinTangential>,
    models::ContactLaw<models::JkrFull, models::NoAdhesion, models::MindlinTangential>,
    models::ContactLaw<models::HertzTsuji, models::CapillaryBridge, models::NoFriction>,
    models::ContactLaw<models::HertzTsuji, models::CapillaryBridge, models::MindlinTangential>>;

template <class Method>
void add_directly_scaled_laws(std::vector<PhysicsEntry>& registry) {
  models::for_each_type(DirectlyScaledLaws{}, [&](auto law) {
    using Law = typename std::decay_t<decltype(law)>::type;
    const std::string name = models::law_name(Law::normal_type::name, Law::adhesion_type::name,
                                              Law::tangential_type::name, Law::rolling_type::name);
    registry.push_back(
        {name + "@" + Method::name, &make_simulation<models::scaling::DirectForceScaling<Method, Law>>});
  });
}

} // namespace cgdem
