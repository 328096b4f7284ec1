// Checks made before a command does any work. See drivers/preflight.hpp.
#include "drivers/preflight.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/frame.hpp"
#include "core/scene.hpp"

namespace cgdem {

namespace fs = std::filesystem;

namespace {

// Creates and removes a temporary file in dir; "" on success, else the reason.
std::string probe_write(const fs::path& dir) {
  std::string tmpl = (dir / ".cgdem-write-probe-XXXXXX").string();
  const int fd = ::mkstemp(tmpl.data());
  if (fd < 0) return std::strerror(errno);
  ::close(fd);
  ::unlink(tmpl.c_str());
  return "";
}

std::string gib(double bytes) {
  char s[32];
  std::snprintf(s, sizeof s, "%.3g GiB", bytes / (1024.0 * 1024.0 * 1024.0));
  return s;
}

} // namespace

std::string output_file_problem(const std::string& path) {
  if (path.empty()) return "(empty output path): no file name; give one with --out FILE.h5";
  std::error_code ec;
  const fs::path p = fs::absolute(path, ec);
  if (fs::is_directory(p, ec))
    return path + ": is a directory, not a file; give a file name, e.g. --out " +
           (fs::path(path) / "results.h5").string();
  const fs::path dir = p.parent_path();
  if (!fs::exists(dir, ec))
    return path + ": output directory '" + dir.string() +
           "' does not exist; create it (mkdir -p) or choose another path with --out";
  if (!fs::is_directory(dir, ec))
    return path + ": '" + dir.string() + "' is not a directory; choose another path with --out";
  if (const std::string why = probe_write(dir); !why.empty())
    return path + ": cannot create files in '" + dir.string() + "' (" + why +
           "); choose a writable directory with --out";
  return "";
}

std::string output_dir_problem(const std::string& dir) {
  if (dir.empty()) return "(empty output directory): give one with --out DIR";
  std::error_code ec;
  fs::path p = fs::absolute(dir, ec);
  if (fs::exists(p, ec) && !fs::is_directory(p, ec))
    return dir + ": exists and is not a directory; choose another directory with --out";
  while (!fs::exists(p, ec) && p.has_parent_path() && p != p.parent_path())
    p = p.parent_path();
  if (!fs::is_directory(p, ec))
    return dir + ": '" + p.string() + "' is not a directory; choose another directory with --out";
  if (const std::string why = probe_write(p); !why.empty())
    return dir + ": cannot create files in '" + p.string() + "' (" + why +
           "); choose a writable directory with --out";
  return "";
}

double machine_memory_bytes() {
  double bytes = double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGESIZE));
  {
    std::ifstream in("/sys/fs/cgroup/memory.max"); // cgroup v2; "max" when unlimited
    double limit = 0;
    if (in >> limit && limit > 0) bytes = std::min(bytes, limit);
  }
  for (int res : {RLIMIT_AS, RLIMIT_DATA}) {
    rlimit r{};
    if (::getrlimit(res, &r) == 0 && r.rlim_cur != RLIM_INFINITY) bytes = std::min(bytes, double(r.rlim_cur));
  }
  return bytes;
}

double run_memory_estimate(double particles) {
  // Per particle: the engine holds at least ~300 B after its first neighbour list (the sparsest example
  // scene, scenes/periodic_box.yaml, measured by `cgdem check`); while it is built, the scene's host set and
  // the configuration's copy exist too; and one output frame is in flight.
  const double engine = 300;
  const double host_set = sizeof(std::int64_t) + 3 * sizeof(Vec3d) + 2 * sizeof(double) + 2 * sizeof(int);
  const double frame = double(FrameData::bytes_per_particle());
  return particles * (engine + 2 * host_set + frame);
}

std::string memory_shortfall(double particles) {
  const double need = run_memory_estimate(particles);
  const double have = machine_memory_bytes();
  if (need <= have) return "";
  char n[32];
  std::snprintf(n, sizeof n, "%.4g", particles);
  return std::string(n) + " particles need at least " + gib(need) + " of memory, this machine has " +
         gib(have);
}

} // namespace cgdem
