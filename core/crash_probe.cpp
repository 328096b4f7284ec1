// See core/crash_probe.hpp.
#include "core/crash_probe.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace cgdem {

std::string crash_probe(const std::function<void()>& read) {
  std::fflush(nullptr); // the child must not flush this process's buffered output a second time
  const pid_t pid = ::fork();
  if (pid < 0) return ""; // no child to be had: read directly, as without the probe
  if (pid == 0) {
    try {
      read();
    } catch (...) {
    }
    ::_exit(0);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return "";
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  if (WIFSIGNALED(status))
    return "the file is damaged: reading it crashed the HDF5 library (signal " +
           std::to_string(WTERMSIG(status)) + ")";
  return "the file is damaged: reading it crashed the HDF5 library (exit " +
         std::to_string(WEXITSTATUS(status)) + ")";
}

} // namespace cgdem
