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
};
} // namespace

std::string physics_name(const ContactSpec& c) {
  std::string name = c.normal;
  if (c.adhesion != "none") name += "+" + c.adhesion;
  if (c.tangential != "none") name += "+" + c.tangential;
  if (c.rolling != "none") name += "+" + c.rolling;
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
