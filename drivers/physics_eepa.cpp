// Every sensible combination of components with Thakur's linear EEPA as the normal law.
#include "drivers/physics_factory.hpp"

void cgdem::add_eepa_laws(std::vector<PhysicsEntry>& registry) {
  add_laws_of<models::LinearEepa>(registry);
}
