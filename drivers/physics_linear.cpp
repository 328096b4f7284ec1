// Linear spring-dashpot with the incremental tangential spring.
#include "drivers/physics_factory.hpp"
#include "models/linear_spring_dashpot.hpp"
#include "models/mindlin_tangential.hpp"

using namespace cgdem::models;
CGDEM_DEFINE_PHYSICS(make_linear_mindlin, ContactLaw<LinearSpringDashpot, NoAdhesion, MindlinTangential, NoRolling>)
CGDEM_DEFINE_PHYSICS(make_linear, ContactLaw<LinearSpringDashpot, NoAdhesion, NoFriction, NoRolling>)
