#pragma once
// Time-step estimate (docs/physics.md 5): the stable limit is the smaller of 0.3 Rayleigh times of
// the smallest particle of each material and a tenth of the shortest contact time (Hertz at the
// scene's characteristic impact speed, or the linear / EEPA spring period).
// Coarse-graining (setup/scaling.hpp, docs/coarse_graining.md): chen_elliott takes the ORIGINAL particles'
// limit (contact time invariant under the law); hu_method1 l times the original's (Hu eqs 38-41); every
// other law the limit of the scaled contact (parameter laws: the scaled parameters on the coarse particles;
// hu_method2/3 and sakai: the equivalent coarse Hertz modulus E* l^(f - 0.5 - 1.5 o) or spring k l^(f - o)
// for force power f and overlap power o). Mixed factors: each pair at its pair factor. `time.step: auto`
// takes time.fraction of that limit; a given step above the limit is refused unless time.force_step is set.
#include <string>
#include "core/scene.hpp"

namespace cgdem {

struct TimeStepEstimate {
  double rayleigh_time = 0; // smallest over particle materials
  double contact_time = 0;  // shortest over material pairs
  double limit = 0;         // min(0.3 T_R, t_c / 10)
  // Accuracy cap of the auto step for laws with force jumps (JKR snap-in/snap-off): v dt <= 2e-3 u keeps
  // the energy lost in a collision within 1% of W_s (docs/stability.md). Not a stability limit.
  double accuracy_step = 0;
  double step = 0;          // what the run uses
  std::string reason;       // one line: which law and material set it, and the coarse-graining rule
  std::string rule;         // the coarse-graining time-step rule alone ("" without coarse-graining)
};

double rayleigh_time(double radius, double density, double youngs_modulus, double poisson_ratio);
// Hertz contact time of an elastic impact at relative speed v (Raman 1920 / docs/physics.md 3.1).
double hertz_contact_time(double m_eff, double r_eff, double e_eff, double speed);

TimeStepEstimate estimate_time_step(const Scene& scene, const ParticleSet& particles);

} // namespace cgdem
