// Every sensible combination of components with the normal law number 3 of models::NormalLaws
// (models/component_lists.hpp), on every backend; nothing while the list is shorter.
#include "drivers/physics_factory.hpp"

template void cgdem::add_normal_laws<3>(std::vector<PhysicsEntry>& registry);
