#pragma once
// The cgdem commands. Each returns the process exit code: 0 done, 2 bad input, 3 blow-up.
#include <string>
#include <vector>

namespace cgdem {

int run_command(const std::vector<std::string>& args);

// What `cgdem run SCENE --set ...` checks before its first step, done without running: the scene parsed,
// the particles generated and checked, the time step against its limit, the analyses, the compiled physics,
// and the engine built once (cell grid, neighbour list; Kokkos must be initialized). Throws SceneError
// (file, key, fix) or std::exception for what a run would fail on; otherwise returns the particle count,
// their total mass and the warnings the run would print.
struct RunCheck {
  long particles = 0;
  double mass = 0; // kg
  std::vector<std::string> warnings;
};
RunCheck check_run(const std::string& scene, const std::vector<std::string>& overrides);
int check_command(const std::vector<std::string>& args);
int info_command(const std::vector<std::string>& args);

} // namespace cgdem
