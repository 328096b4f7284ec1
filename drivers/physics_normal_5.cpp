// Every sensible combination of components with the normal law number 5 of models::NormalLaws
// (models/component_lists.hpp), on every backend; nothing while the list is shorter.
#include "drivers/physics_factory.hpp"

template void cgdem::add_normal_laws<5>(std::vector<PhysicsEntry>& registry);
