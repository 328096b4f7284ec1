// See core/crash_probe.hpp.
#include "core/crash_probe.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>

namespace cgdem {

double probe_time_limit(std::uintmax_t bytes) {
  return 5.0 + static_cast<double>(bytes) / 20e6;
}

std::string crash_probe(const std::function<void()>& read, double time_limit_s) {
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
  // Poll for the child's end, 1 ms at first (a good file is read in milliseconds), backing off to 50 ms.
  const auto start = std::chrono::steady_clock::now();
  long wait_ns = 1000000;
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) return "";
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (waited > time_limit_s) {
      ::kill(pid, SIGKILL);
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      char limit[32];
      std::snprintf(limit, sizeof limit, "%.0f", time_limit_s);
      return std::string("the file is damaged: the HDF5 library did not finish reading it in ") + limit +
             " s (it loops on some damaged files)";
    }
    const timespec ts{0, wait_ns};
    ::nanosleep(&ts, nullptr);
    wait_ns = wait_ns < 50000000 ? 2 * wait_ns : wait_ns;
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  if (WIFSIGNALED(status))
    return "the file is damaged: reading it crashed the HDF5 library (signal " +
           std::to_string(WTERMSIG(status)) + ")";
  return "the file is damaged: reading it crashed the HDF5 library (exit " +
         std::to_string(WEXITSTATUS(status)) + ")";
}

} // namespace cgdem
