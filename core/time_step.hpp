#pragma once
// Time-step estimate (physics.md section 3): the stable limit is the smaller of 0.3 Rayleigh times of
// the smallest particle of each material and a tenth of the shortest contact time (Hertz at the
// scene's characteristic impact speed, or the linear / EEPA spring period). `time.step: auto` takes
// time.fraction of that limit; a given step above the limit is refused unless time.force_step is set.
#include <string>
#include "core/scene.hpp"

namespace cgdem {

struct TimeStepEstimate {
  double rayleigh_time = 0;   // smallest over particle materials
  double contact_time = 0;    // shortest over material pairs
  double limit = 0;           // min(0.3 T_R, t_c / 10)
  double step = 0;            // what the run uses
  std::string reason;         // one line: which law and material set it
};

double rayleigh_time(double radius, double density, double youngs_modulus, double poisson_ratio);
// Hertz contact time of an elastic impact at relative speed v (Raman 1920 / physics.md).
double hertz_contact_time(double m_eff, double r_eff, double e_eff, double speed);

TimeStepEstimate estimate_time_step(const Scene& scene, const ParticleSet& particles);

} // namespace cgdem
