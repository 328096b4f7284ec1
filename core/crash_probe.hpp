#pragma once
// Reading an untrusted file with a library that may crash or loop on it (libhdf5 1.10 dereferences
// addresses taken from a damaged file, and spins forever on some: docs/reliability.md): the read is first
// done in a forked child, and only if the child finishes in time is it done for real in this process.
#include <cstdint>
#include <functional>
#include <string>

namespace cgdem {

// Time a read of a file of `bytes` may take in the probe before it counts as hung: 5 s plus 1 s per 20 MB,
// far above what libhdf5 needs for a good file (a checkpoint of a million particles reads in well under a
// second) and still short of a user's patience.
double probe_time_limit(std::uintmax_t bytes);

// Runs `read` in a child process (exceptions are the caller's business and ignored there). Returns "" if
// the child finished, else why not ("... crashed the HDF5 library (signal 11)", "... did not finish ...";
// a child past `time_limit_s` seconds is killed). Call it with no HDF5 lock held and before the result
// writer starts (no other thread in HDF5).
std::string crash_probe(const std::function<void()>& read, double time_limit_s);

} // namespace cgdem
