#pragma once
// Command-line handling of the cgdem executable: options of each command and their help texts.
#include <stdexcept>
#include <string>
#include <vector>

namespace cgdem {

struct CliError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct RunOptions {
  std::string scene;
  std::vector<std::string> overrides;  // --set key.path=value
  std::string out;                     // --out (default: the scene's output.file)
  int threads = 0;                     // 0: Kokkos/OpenMP default
  std::string backend;                 // openmp | serial | cuda (default: the first compiled)
  double checkpoint_every = 0;         // simulated seconds; 0: off
  std::string restart;                 // checkpoint to continue from
  bool quiet = false;                  // no progress line
};

// Parses `args` (after the command word). Throws CliError with a one-line message.
RunOptions parse_run_options(const std::vector<std::string>& args, bool allow_run_only_options);

const char* main_help();
const char* run_help();
const char* check_help();
const char* info_help();

} // namespace cgdem
