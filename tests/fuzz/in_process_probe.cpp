// The fuzz targets' stand-in for core/crash_probe.cpp: the read runs in this process, once.
// cgdem forks a probe child before reading an HDF5 input so that a crash inside libhdf5 becomes an error
// message; under ASan a fork costs most of a millisecond-scale execution, so the fuzzers would run at a few
// inputs per second. Here libFuzzer's fork mode (scripts/fuzz.sh) contains what the probe contains in
// cgdem: a crash or hang inside libhdf5 ends one fuzzing job, is saved under findings/, and fuzzing goes on.
// The probe itself is tested by Checkpoint.FuzzedFilesThatCrashedHdf5GiveAnError.
#include <functional>
#include <string>

#include "core/crash_probe.hpp"

namespace cgdem {

double probe_time_limit(std::uintmax_t) {
  return 0.0;
}

std::string crash_probe(const std::function<void()>&, double) {
  return {};
}

} // namespace cgdem
