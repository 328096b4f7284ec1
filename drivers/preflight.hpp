#pragma once
// Checks made before a command does any work: can its outputs be written, and does the scene fit in memory.
// Each returns "" when all is well, else one line "<path>: <what is wrong>; <the fix>" for exit code 2.
#include <cstddef>
#include <string>

namespace cgdem {

// Exit codes shared by the commands (README, "Commands").
constexpr int exit_bad_input = 2;
constexpr int exit_blow_up = 3;
constexpr int exit_write_failed =
    4; // an output could not be written during the run (disk full, removed, ...)

// A file the command will create or replace (result, XDMF, checkpoint): not a directory, in an existing
// directory where a file can really be created (probed with a temporary file, so a read-only file system
// or a non-directory parent is caught even for root).
std::string output_file_problem(const std::string& path);

// A directory the command will create or fill (sweep, stability): an existing directory that can be
// written, or a new one whose nearest existing ancestor can be written.
std::string output_dir_problem(const std::string& dir);

// Memory the machine offers this process: the smallest of physical memory, the cgroup limit and
// RLIMIT_AS / RLIMIT_DATA.
double machine_memory_bytes();

// Lower-bound estimate of the memory a run of n particles takes at its peak (host copies while the engine is
// built, the engine's store and first neighbour list, one output frame).
double run_memory_estimate(double particles);

// "" if n particles fit, else what is wrong with both figures ("N particles need at least X GiB of memory,
// this machine has Y GiB").
std::string memory_shortfall(double particles);

} // namespace cgdem
