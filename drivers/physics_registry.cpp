// The single place where a scene's law names become a compiled type: a closed list of the contact-law
// combinations built into cgdem (a scene runs only the physics it names).
#include <Kokkos_Core.hpp>
#include <sstream>
#include "kernels/engine.hpp"

namespace cgdem {

using Factory = std::unique_ptr<Engine> (*)(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_mindlin(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_linear_mindlin(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_linear(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_mindlin_ct(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_mindlin_sd(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_jkr(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_jkr_mindlin(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_jkr_mindlin_sd(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_dmt_mindlin(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_capillary_mindlin(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_capillary(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_eepa_mindlin(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_eepa_mindlin_ct(const EngineConfig&, const std::string&, const std::string&);
// Direct force scaling (drivers/physics_scaled_<method>.cpp): the same laws wrapped per method.
std::unique_ptr<Engine> make_hertz_mindlin_hu_method1(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_jkr_mindlin_hu_method1(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_capillary_hu_method1(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_mindlin_hu_method2(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_jkr_mindlin_hu_method2(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_capillary_hu_method2(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_mindlin_hu_method3(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_jkr_mindlin_hu_method3(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_capillary_hu_method3(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_mindlin_sakai(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_jkr_mindlin_sakai(const EngineConfig&, const std::string&, const std::string&);
std::unique_ptr<Engine> make_hertz_capillary_sakai(const EngineConfig&, const std::string&, const std::string&);

namespace {
struct Entry {
  const char* name;
  Factory make;
};
const Entry registry[] = {
    {"hertz+mindlin", make_hertz_mindlin},
    {"hertz", make_hertz},
    {"linear+mindlin", make_linear_mindlin},
    {"linear", make_linear},
    {"hertz+mindlin+constant_torque", make_hertz_mindlin_ct},
    {"hertz+mindlin+spring_dashpot", make_hertz_mindlin_sd},
    {"jkr", make_jkr},
    {"jkr+mindlin", make_jkr_mindlin},
    {"jkr+mindlin+spring_dashpot", make_jkr_mindlin_sd},
    {"hertz+dmt+mindlin", make_hertz_dmt_mindlin},
    {"hertz+capillary+mindlin", make_hertz_capillary_mindlin},
    {"hertz+capillary", make_hertz_capillary},
    {"eepa+mindlin", make_eepa_mindlin},
    {"eepa+mindlin+constant_torque", make_eepa_mindlin_ct},
    {"hertz+mindlin@hu_method1", make_hertz_mindlin_hu_method1},
    {"jkr+mindlin@hu_method1", make_jkr_mindlin_hu_method1},
    {"hertz+capillary@hu_method1", make_hertz_capillary_hu_method1},
    {"hertz+mindlin@hu_method2", make_hertz_mindlin_hu_method2},
    {"jkr+mindlin@hu_method2", make_jkr_mindlin_hu_method2},
    {"hertz+capillary@hu_method2", make_hertz_capillary_hu_method2},
    {"hertz+mindlin@hu_method3", make_hertz_mindlin_hu_method3},
    {"jkr+mindlin@hu_method3", make_jkr_mindlin_hu_method3},
    {"hertz+capillary@hu_method3", make_hertz_capillary_hu_method3},
    {"hertz+mindlin@sakai", make_hertz_mindlin_sakai},
    {"jkr+mindlin@sakai", make_jkr_mindlin_sakai},
    {"hertz+capillary@sakai", make_hertz_capillary_sakai},
};
} // namespace

std::string physics_name(const ContactSpec& c) {
  std::string name = c.normal;
  if (c.adhesion != "none") name += "+" + c.adhesion;
  if (c.tangential != "none") name += "+" + c.tangential;
  if (c.rolling != "none") name += "+" + c.rolling;
  if (c.scaling != "none") name += "@" + c.scaling;  // direct force scaling wraps the whole law
  return name;
}

std::vector<std::string> compiled_physics() {
  std::vector<std::string> out;
  for (const Entry& e : registry) out.push_back(e.name);
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
  for (const Entry& e : registry)
    if (name == e.name) return e.make(config, name, backend);
  std::ostringstream msg;
  msg << "contact law '" << name << "' is not compiled into cgdem; compiled:";
  for (const Entry& e : registry) msg << " " << e.name;
  throw std::invalid_argument(msg.str());
}

} // namespace cgdem
