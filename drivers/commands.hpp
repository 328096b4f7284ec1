#pragma once
// The cgdem commands. Each returns the process exit code: 0 done, 2 bad input, 3 blow-up.
#include <string>
#include <vector>

namespace cgdem {

int run_command(const std::vector<std::string>& args);
int check_command(const std::vector<std::string>& args);
int info_command(const std::vector<std::string>& args);

} // namespace cgdem
