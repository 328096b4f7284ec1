// Hertz-Mindlin with Tsuji damping, with and without rolling resistance... (compiled laws, see registry).
#include "drivers/physics_factory.hpp"
#include "models/hertz_tsuji.hpp"
#include "models/mindlin_tangential.hpp"

using namespace cgdem::models;
CGDEM_DEFINE_PHYSICS(make_hertz_mindlin, ContactLaw<HertzTsuji, NoAdhesion, MindlinTangential, NoRolling>)
CGDEM_DEFINE_PHYSICS(make_hertz, ContactLaw<HertzTsuji, NoAdhesion, NoFriction, NoRolling>)
