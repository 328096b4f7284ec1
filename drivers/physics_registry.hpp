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

// One per translation unit: the sensible combinations of the I-th normal law of models::NormalLaws
// (drivers/physics_normal_<I>.cpp; nothing when the list is shorter), and the direct scaling methods.
inline constexpr int kNormalLawUnits = 6;
template <int I>
void add_normal_laws(std::vector<PhysicsEntry>& registry);
extern template void add_normal_laws<0>(std::vector<PhysicsEntry>&);
extern template void add_normal_laws<1>(std::vector<PhysicsEntry>&);
extern template void add_normal_laws<2>(std::vector<PhysicsEntry>&);
extern template void add_normal_laws<3>(std::vector<PhysicsEntry>&);
extern template void add_normal_laws<4>(std::vector<PhysicsEntry>&);
extern template void add_normal_laws<5>(std::vector<PhysicsEntry>&);
void add_hu_method1_laws(std::vector<PhysicsEntry>& registry);
void add_hu_method2_laws(std::vector<PhysicsEntry>& registry);
void add_hu_method3_laws(std::vector<PhysicsEntry>& registry);
void add_sakai_laws(std::vector<PhysicsEntry>& registry);

} // namespace cgdem
