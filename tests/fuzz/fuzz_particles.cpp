// libFuzzer target: the particle file readers behind placement: {type: file} (CSV and cgdem HDF5,
// drivers/particle_generation.hpp). The input is written to a file that a fixed scene names; the file's
// first bytes choose the reader as in cgdem (HDF5 signature or CSV). Every input must end in particles or
// a SceneError.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "drivers/particle_generation.hpp"
#include "drivers/scene_parser.hpp"

namespace {

const std::string& input_path() {
  static const std::string p = "/tmp/cgdem_fuzz_particles_" + std::to_string(::getpid());
  return p;
}

const cgdem::Scene& scene() {
  static const cgdem::Scene s = cgdem::parse_scene_text(
      "domain: {lo: [-1, -1, -1], hi: [1, 1, 1]}\n"
      "materials: {m: {density: 2500, youngs_modulus: 1e7, poisson_ratio: 0.3, restitution: 0.5, "
      "friction: 0.3}}\n"
      "groups:\n  - {name: g, material: m, placement: {type: file, file: " +
          input_path() +
          "}}\n"
          "time: {end: 0.001}\n",
      "fuzz.yaml");
  return s;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::FILE* f = std::fopen(input_path().c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    const cgdem::ParticleSet ps = cgdem::generate_particles(scene());
    cgdem::check_particles(scene(), ps);
  } catch (const cgdem::SceneError&) {
  }
  return 0;
}
