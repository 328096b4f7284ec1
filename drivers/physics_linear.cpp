// Every sensible combination of components with the linear spring-dashpot as the normal law.
#include "drivers/physics_factory.hpp"

void cgdem::add_linear_laws(std::vector<PhysicsEntry>& registry) {
  add_laws_of<models::LinearSpringDashpot>(registry);
}
