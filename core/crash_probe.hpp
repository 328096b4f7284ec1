#pragma once
// Reading an untrusted file with a library that may crash on it (libhdf5 1.10 dereferences addresses taken
// from a damaged file: docs/reliability.md): the read is first done in a forked child, and only if the
// child finishes is it done for real in this process.
#include <functional>
#include <string>

namespace cgdem {

// Runs `read` in a child process (exceptions are the caller's business and ignored there). Returns "" if
// the child finished, else why not ("the reader crashed (signal 11)"). Call it with no HDF5 lock held
// and before the result writer starts (no other thread in HDF5).
std::string crash_probe(const std::function<void()>& read);

} // namespace cgdem
