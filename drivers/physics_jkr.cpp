// Every sensible combination of components with full JKR (Chen's and Hu's) as the normal law.
#include "drivers/physics_factory.hpp"

void cgdem::add_jkr_laws(std::vector<PhysicsEntry>& registry) {
  add_laws_of<models::JkrFull>(registry);
}
