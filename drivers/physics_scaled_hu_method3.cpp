// Direct force scaling hu_method3 (models/scaling/direct_force_scaling.hpp) around the laws it is validated
// with; registered as "<law>@hu_method3".
#include "drivers/physics_factory.hpp"

void cgdem::add_hu_method3_laws(std::vector<PhysicsEntry>& registry) {
  add_directly_scaled_laws<models::scaling::HuMethod3>(registry);
}
