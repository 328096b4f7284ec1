// The single place where a scene's law names become a compiled type: the contact-law combinations built
// into cgdem, generated from the component lists (a scene runs only the physics it names).
#include <Kokkos_Core.hpp>
#include <sstream>
#include "drivers/physics_registry.hpp"
#include "models/component_lists.hpp"

namespace cgdem {

namespace {
// Built once, on first use, from the translation units that instantiate the laws.
const std::vector<PhysicsEntry>& registry() {
  static const std::vector<PhysicsEntry> all = [] {
    std::vector<PhysicsEntry> r;
    static_assert(models::list_size(models::NormalLaws{}) <= kNormalLawUnits,
                  "more normal laws than translation units: add drivers/physics_normal_<i>.cpp for the new "
                  "index and raise kNormalLawUnits (drivers/physics_registry.hpp)");
    for (auto add :
         {add_normal_laws<0>, add_normal_laws<1>, add_normal_laws<2>, add_normal_laws<3>, add_normal_laws<4>,
          add_normal_laws<5>, add_hu_method1_laws, add_hu_method2_laws, add_hu_method3_laws, add_sakai_laws})
      add(r);
    return r;
  }();
  return all;
}
} // namespace

std::string physics_name(const ContactSpec& c) {
  std::string name = models::law_name(c.normal, c.adhesion, c.tangential, c.rolling);
  if (c.scaling != "none") name += "@" + c.scaling; // direct force scaling wraps the whole law
  return name;
}

std::vector<std::string> compiled_physics() {
  std::vector<std::string> out;
  for (const PhysicsEntry& e : registry())
    out.push_back(e.name);
  return out;
}

std::vector<std::string> compiled_backends() {
  std::vector<std::string> out;
#if defined(KOKKOS_ENABLE_OPENMP)
  out.push_back("openmp");
#endif
#if defined(KOKKOS_ENABLE_SERIAL)
  out.push_back("serial");
#endif
#if defined(KOKKOS_ENABLE_CUDA)
  out.push_back("cuda");
#endif
  return out;
}

std::unique_ptr<Engine> make_engine(const EngineConfig& config, const std::string& backend) {
  const std::string name = physics_name(config.contact);
  for (const PhysicsEntry& e : registry())
    if (name == e.name) return e.make(config, name, backend);
  std::ostringstream msg;
  msg << "contact law '" << name << "' is not compiled into cgdem; compiled:";
  for (const PhysicsEntry& e : registry())
    msg << " " << e.name;
  throw std::invalid_argument(msg.str());
}

} // namespace cgdem
