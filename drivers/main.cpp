// cgdem: the batch executable. Dispatches to the commands in drivers/commands.cpp.
#include <hdf5.h>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>
#include "drivers/analyse_command.hpp"
#include "drivers/cli.hpp"
#include "drivers/commands.hpp"
#include "drivers/sweep_command.hpp"
#include "drivers/stability_command.hpp"
#include "parallel/mpi_session.hpp"

int main(int argc, char** argv) {
  // No HDF5 clean-up at exit: after a write failed (disk full) HDF5 keeps the file whose close failed and
  // crashes closing it again at exit. Every file cgdem writes is closed and fsync'ed explicitly before.
  H5dont_atexit();
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
      !std::strcmp(argv[1], "help")) {
    std::cout << cgdem::main_help();
    return argc < 2 ? 2 : 0;
  }
  if (!std::strcmp(argv[1], "--version")) argv[1] = const_cast<char*>("info");
  cgdem::parallel::MpiSession mpi(argc, argv);
  const std::string command = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  if (command == "run") return cgdem::run_command(args);
  if (command == "sweep") return cgdem::sweep_command(args);
  if (cgdem::parallel::world_size() > 1) {
    if (cgdem::parallel::world_rank() == 0)
      std::cerr << "cgdem: '" << command
                << "' runs in one process; 'cgdem run' and 'cgdem sweep' spread over MPI ranks\n";
    return 2;
  }
  if (command == "check") return cgdem::check_command(args);
  if (command == "info") return cgdem::info_command(args);
  if (command == "stability") return cgdem::stability_command(args);
  if (command == "analyse" || command == "analyze") return cgdem::analyse_command(args);
  std::cerr << "cgdem: unknown command '" << command
            << "'; commands: run, check, info, sweep, stability, analyse (see cgdem --help)\n";
  return 2;
}
