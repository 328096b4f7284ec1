// Direct force scaling hu_method2 (models/scaling/direct_force_scaling.hpp) around the laws it is validated
// with; registered as "<law>@hu_method2".
#include "drivers/physics_factory.hpp"

void cgdem::add_hu_method2_laws(std::vector<PhysicsEntry>& registry) {
  add_directly_scaled_laws<models::scaling::HuMethod2>(registry);
}
