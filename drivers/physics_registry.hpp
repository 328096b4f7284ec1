#pragma once
// The compiled contact laws: one entry per law a scene can name, filled by the drivers/physics_*.cpp
// translation units from the component lists (models/component_lists.hpp).
#include <memory>
#include <string>
#include <vector>
#include "kernels/engine.hpp"

namespace cgdem {

struct PhysicsEntry {
  std::string name; // normal[+adhesion][+tangential][+rolling][@direct scaling method]
  std::unique_ptr<Engine> (*make)(const EngineConfig&, const std::string& physics,
                                  const std::string& backend);
};

// One per translation unit: the normal laws' sensible combinations, and the direct scaling methods.
void add_hertz_laws(std::vector<PhysicsEntry>& registry);
void add_linear_laws(std::vector<PhysicsEntry>& registry);
void add_jkr_laws(std::vector<PhysicsEntry>& registry);
void add_eepa_laws(std::vector<PhysicsEntry>& registry);
void add_hu_method1_laws(std::vector<PhysicsEntry>& registry);
void add_hu_method2_laws(std::vector<PhysicsEntry>& registry);
void add_hu_method3_laws(std::vector<PhysicsEntry>& registry);
void add_sakai_laws(std::vector<PhysicsEntry>& registry);

} // namespace cgdem
