// Hertz with Tsuji damping: frictionless, with the Mindlin tangential spring, and with rolling resistance.
#include "drivers/physics_factory.hpp"
#include "models/hertz_tsuji.hpp"
#include "models/mindlin_tangential.hpp"

using namespace cgdem::models;
CGDEM_DEFINE_PHYSICS(make_hertz_mindlin, ContactLaw<HertzTsuji, NoAdhesion, MindlinTangential, NoRolling>)
CGDEM_DEFINE_PHYSICS(make_hertz, ContactLaw<HertzTsuji, NoAdhesion, NoFriction, NoRolling>)
#include "models/rolling_resistance.hpp"
CGDEM_DEFINE_PHYSICS(make_hertz_mindlin_ct, ContactLaw<HertzTsuji, NoAdhesion, MindlinTangential, RollingConstantTorque>)
CGDEM_DEFINE_PHYSICS(make_hertz_mindlin_sd, ContactLaw<HertzTsuji, NoAdhesion, MindlinTangential, RollingSpringDashpot>)
