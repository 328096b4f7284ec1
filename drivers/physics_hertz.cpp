// Every sensible combination of components with Hertz with Tsuji damping as the normal law.
#include "drivers/physics_factory.hpp"

void cgdem::add_hertz_laws(std::vector<PhysicsEntry>& registry) {
  add_laws_of<models::HertzTsuji>(registry);
}
