#pragma once
// Scene (validated) + particles -> EngineConfig: pair tables, wall parts, time step and skin.
#include "setup/engine_config.hpp"
#include "setup/time_step.hpp"

namespace cgdem {

EngineConfig make_engine_config(const Scene& scene, const ParticleSet& particles, const TimeStepEstimate& dt);

} // namespace cgdem
