// Direct force scaling hu_method1 (models/scaling/direct_force_scaling.hpp) around the laws it is validated
// with; registered as "<law>@hu_method1".
#include "drivers/physics_factory.hpp"

void cgdem::add_hu_method1_laws(std::vector<PhysicsEntry>& registry) {
  add_directly_scaled_laws<models::scaling::HuMethod1>(registry);
}
