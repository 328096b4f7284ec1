// Direct force scaling sakai (models/scaling/direct_force_scaling.hpp) around the laws it is validated
// with; registered as "<law>@sakai".
#include "drivers/physics_factory.hpp"

void cgdem::add_sakai_laws(std::vector<PhysicsEntry>& registry) {
  add_directly_scaled_laws<models::scaling::Sakai>(registry);
}
