// libFuzzer target: the checkpoint reader (core/checkpoint.hpp), as `cgdem run --restart FILE` calls it.
// Every input must end in a CheckpointData or a std::runtime_error naming the file.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "core/checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/cgdem_fuzz_checkpoint_" + std::to_string(::getpid()) + ".h5";
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    cgdem::read_checkpoint(path);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
