#include "drivers/sweep_command.hpp"
#include "drivers/preflight.hpp"
#include <fcntl.h>
#include <hdf5.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>
#include "core/result_writer.hpp"
#include "drivers/analyses.hpp"
#include "drivers/cli.hpp"
#include "drivers/commands.hpp"
#include "drivers/kokkos_session.hpp"
#include "drivers/scene_parser.hpp"
#include "drivers/sweep_statistics.hpp"
#include "parallel/mpi_session.hpp"

extern char** environ;

namespace cgdem {

namespace fs = std::filesystem;

namespace {

// Measured on the tiny scene (docs/sweeps.md, "Scheduling"): one single-threaded process per core beat one
// run at a time on all threads.
constexpr const char* kAutoPolicy = "parallel";
constexpr std::size_t kMaxSamples = 2000;

std::string fmt(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

std::string k_name(double k) {
  char b[40];
  std::snprintf(b, sizeof b, "%g", k);
  return b;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, sep))
    if (!item.empty()) out.push_back(item);
  return out;
}

// ---- HDF5: what a finished run's file says ----

struct RunOutput {
  long particles = 0, steps = 0, last_step = 0;
  int threads = 1;
  double time_step = 0;
  std::map<std::string, double> final_values;
  FrameData last; // velocity and group of the last frame
};

struct H5 {
  hid_t id;
  herr_t (*close)(hid_t);
  H5(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  ~H5() {
    if (id >= 0) close(id);
  }
  operator hid_t() const { return id; }
};

std::vector<double> read_doubles(hid_t loc, const std::string& name,
                                 std::vector<hsize_t>* dims_out = nullptr) {
  H5 ds(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds < 0) throw std::runtime_error("cannot open dataset " + name);
  H5 space(H5Dget_space(ds), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(std::max(rank, 1), 1);
  if (rank > 0) H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  hsize_t n = 1;
  for (int r = 0; r < rank; ++r)
    n *= dims[r];
  std::vector<double> v(n);
  if (n > 0 && H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0)
    throw std::runtime_error("cannot read dataset " + name);
  if (dims_out) *dims_out = dims;
  return v;
}

double read_attr(hid_t loc, const char* name, double fallback) {
  if (H5Aexists(loc, name) <= 0) return fallback;
  H5 a(H5Aopen(loc, name, H5P_DEFAULT), H5Aclose);
  double v = fallback;
  H5Aread(a, H5T_NATIVE_DOUBLE, &v);
  return v;
}

std::vector<std::string> links(hid_t group) {
  std::vector<std::string> names;
  H5Literate(
      group, H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5L_info_t*, void* d) -> herr_t {
        static_cast<std::vector<std::string>*>(d)->push_back(name);
        return 0;
      },
      &names);
  return names;
}

RunOutput read_run_output(const std::string& path) {
  std::lock_guard<std::mutex> lock(hdf5_mutex());
  RunOutput o;
  H5 file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (file < 0) throw std::runtime_error("cannot open " + path);
  o.time_step = read_attr(file, "time_step", 0);
  o.threads = static_cast<int>(read_attr(file, "threads", 1));
  H5 series(H5Gopen2(file, "series", H5P_DEFAULT), H5Gclose);
  const std::set<std::string> builtin{"time",     "step",       "kinetic_energy", "rotational_energy",
                                      "contacts", "wall_force", "wall_torque"};
  for (const auto& name : links(series)) {
    if (builtin.count(name)) continue;
    const auto v = read_doubles(series, name);
    if (!v.empty()) o.final_values[name] = v.back();
  }
  const auto steps = read_doubles(series, "step");
  if (steps.size() >= 2) o.steps = std::lround(steps.back() - steps.front());
  if (!steps.empty()) o.last_step = std::lround(steps.back());
  H5 frames(H5Gopen2(file, "frames", H5P_DEFAULT), H5Gclose);
  auto names = links(frames);
  if (names.empty()) throw std::runtime_error(path + " has no frames");
  std::sort(names.begin(), names.end());
  H5 last(H5Gopen2(frames, names.back().c_str(), H5P_DEFAULT), H5Gclose);
  std::vector<hsize_t> dims;
  const auto id = read_doubles(last, "id", &dims);
  o.particles = static_cast<long>(id.size());
  o.last.id.assign(id.begin(), id.end());
  if (H5Lexists(last, "velocity", H5P_DEFAULT) > 0) o.last.velocity = read_doubles(last, "velocity");
  if (H5Lexists(last, "group", H5P_DEFAULT) > 0) {
    const auto g = read_doubles(last, "group");
    o.last.group.assign(g.begin(), g.end());
  }
  return o;
}

// ---- one run as a child process ----

struct RunPlan {
  std::string run, law;
  double k = 1;
  std::vector<std::string> sets; // the sweep's own --set overrides
  long particles = 0;            // from the check before the sweep starts
  double mass = 0;               // kg
  long seed = -1;                // the --seeds entry (-1: none)
};

std::string self_exe() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) throw std::runtime_error("cannot find the cgdem executable (/proc/self/exe)");
  buf[n] = 0;
  return buf;
}

// Runs argv in `dir` with stdout+stderr to `log`; returns the wait status. The child dies with the thread
// that waits for it (PR_SET_PDEATHSIG), so killing the sweep leaves no orphan writing into a run directory.
// Runs the child and waits; *cpu_seconds receives its user + system time (rusage of the child).
int spawn_and_wait(const std::vector<std::string>& argv, const std::vector<std::string>& env,
                   const std::string& dir, const std::string& log, bool append_log, double* cpu_seconds) {
  const int log_flags = O_WRONLY | O_CREAT | (append_log ? O_APPEND : O_TRUNC);
  std::vector<char*> a, e;
  for (const auto& s : argv)
    a.push_back(const_cast<char*>(s.c_str()));
  a.push_back(nullptr);
  for (const auto& s : env)
    e.push_back(const_cast<char*>(s.c_str()));
  e.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    // Only async-signal-safe calls between fork and exec.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);
    if (chdir(dir.c_str()) != 0) _exit(127);
    const int fd = open(log.c_str(), log_flags, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    execve(a[0], a.data(), e.data());
    _exit(127);
  }
  int status = 0;
  struct rusage usage {};
  while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  const auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  *cpu_seconds = seconds(usage.ru_utime) + seconds(usage.ru_stime);
  return status;
}

// "done...: S steps of N particles in T: R particle-steps/s" -> R (0 if absent).
double engine_rate_from_log(const std::string& log) {
  std::ifstream in(log);
  std::string line;
  double rate = 0;
  while (std::getline(in, line)) {
    if (line.rfind("done", 0) != 0) continue;
    const auto end = line.find(" particle-steps/s");
    const auto colon = line.rfind(": ", end);
    if (end != std::string::npos && colon != std::string::npos)
      rate = std::atof(line.substr(colon + 2).c_str());
  }
  return rate;
}

std::string tail(const std::string& log, std::size_t lines) {
  std::ifstream in(log);
  std::vector<std::string> all;
  std::string line;
  while (std::getline(in, line))
    all.push_back(line);
  std::string out;
  for (std::size_t i = all.size() > lines ? all.size() - lines : 0; i < all.size(); ++i)
    out += "    " + all[i] + "\n";
  return out;
}

// A run continued from checkpoints is done in pieces, one process each. When a piece starts, its start
// (wall-clock seconds since the epoch, first step) goes to <stage>piece_start.txt; when the next one
// starts, the stopped piece's share, from its start to its last checkpoint (step and file time), is added
// to <stage>pieces.txt. The work after that checkpoint was lost and is done again by the next piece. A
// first stage (--first-stage) keeps its own pair of files (stage "first_stage_"), the run's have none.
struct Pieces {
  int count = 0;      // pieces before the one about to start
  long last_step = 0; // where the checkpoint stands
  double wall = 0;    // seconds of the earlier pieces, each up to its last checkpoint
};

double epoch_seconds() {
  timespec t{};
  clock_gettime(CLOCK_REALTIME, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

void start_piece(const fs::path& rundir, long first_step, const std::string& stage = "") {
  std::ofstream(rundir / (stage + "piece_start.txt")) << fmt(epoch_seconds()) << " " << first_step << "\n";
}

Pieces continue_pieces(const fs::path& rundir, const fs::path& checkpoint, const std::string& stage = "") {
  Pieces p;
  {
    std::lock_guard<std::mutex> lock(hdf5_mutex());
    H5 file(H5Fopen(checkpoint.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (file < 0) throw std::runtime_error("cannot open checkpoint " + checkpoint.string());
    p.last_step = std::lround(read_attr(file, "step", 0));
  }
  struct stat st {};
  const double written =
      stat(checkpoint.c_str(), &st) == 0 ? double(st.st_mtim.tv_sec) + 1e-9 * double(st.st_mtim.tv_nsec) : 0;
  double started = 0;
  long first = 0;
  std::ifstream(rundir / (stage + "piece_start.txt")) >> started >> first;
  if (started > 0 && written > started && p.last_step > first)
    std::ofstream(rundir / (stage + "pieces.txt"), std::ios::app)
        << first << " " << p.last_step << " " << fmt(written - started) << "\n";
  std::ifstream in(rundir / (stage + "pieces.txt"));
  long from = 0, to = 0;
  double seconds = 0;
  while (in >> from >> to >> seconds) {
    ++p.count;
    p.wall += seconds;
  }
  return p;
}

struct Sweep {
  SweepOptions o;
  Scene scene; // with the user's overrides
  std::vector<std::unique_ptr<Analysis>> analyses;
  std::string exe, scene_abs;
  fs::path dir;
  std::mutex print;
  std::atomic<int> done{0};
  int total = 0;

  fs::path record_path(const std::string& run) const { return dir / "records" / (run + ".txt"); }

  // A child `cgdem run` and its wall and CPU seconds.
  struct Child {
    int status = 0;
    double wall = 0, cpu = 0;
  };
  static Child run_child(const std::vector<std::string>& argv, const std::vector<std::string>& env,
                         const fs::path& rundir, const std::string& log, bool append_log) {
    Child c;
    const auto start = std::chrono::steady_clock::now();
    c.status = spawn_and_wait(argv, env, rundir.string(), log, append_log, &c.cpu);
    c.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return c;
  }

  // True (and said) when the child died of a signal: the run is not complete and runs again next time.
  bool killed(const RunPlan& plan, int status, const char* where) {
    if (WIFEXITED(status)) return false;
    std::lock_guard<std::mutex> lock(print);
    std::fprintf(stderr, "sweep: run %s was killed%s (signal %d); it will run again next time\n",
                 plan.run.c_str(), where, WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    return true;
  }

  RunRecord plan_record(const RunPlan& plan, int threads) const {
    RunRecord r;
    r.run = plan.run;
    r.law = plan.law;
    r.k = plan.k;
    r.seed = plan.seed;
    r.threads = threads;
    r.mass = plan.mass;
    return r;
  }

  // Writes the run's record and says how it ended.
  void finish(const RunRecord& r, const std::string& log) {
    write_record(record_path(r.run).string(), r);
    const int n = ++done;
    std::lock_guard<std::mutex> lock(print);
    if (r.exit_code != 0)
      std::fprintf(stderr, "[%d/%d] %s: %s; last lines of %s:\n%s", n, total, r.run.c_str(), r.status.c_str(),
                   log.c_str(), tail(log, 4).c_str());
    else if (!o.quiet)
      std::fprintf(stderr, "[%d/%d] %-24s %7ld particles %8ld steps  %8.2f s  %.3g particle-steps/s\n", n,
                   total, r.run.c_str(), r.particles, r.steps, r.wall_time, r.particle_steps_per_s);
  }

  // Returns false when the child was killed (no record: the run is not complete).
  bool execute(const RunPlan& plan, int threads, bool unpin) {
    const fs::path rundir = dir / "runs" / plan.run;
    const std::string h5 = (rundir / "run.h5").string(), log = (rundir / "log.txt").string();
    const fs::path checkpoint = rundir / "run.checkpoint.h5";
    const bool resume = o.checkpoint_every > 0 && fs::exists(checkpoint);
    Pieces pieces;
    const bool staged = !o.first_stage.empty();
    const fs::path stage_done = rundir / "first_stage.done",
                   stage_checkpoint = rundir / "first_stage.checkpoint.h5";
    if (resume) {
      pieces = continue_pieces(rundir, checkpoint);
      // The earlier pieces' frames stay beside the continuation's, which writes run.h5 afresh.
      int part = 1;
      while (fs::exists(rundir / ("run.part" + std::to_string(part) + ".h5")))
        ++part;
      std::error_code ec;
      fs::rename(h5, rundir / ("run.part" + std::to_string(part) + ".h5"), ec);
      fs::rename(xdmf_path_for(h5), rundir / ("run.part" + std::to_string(part) + ".xdmf"), ec);
    } else if (!(staged && (fs::exists(stage_done) || fs::exists(stage_checkpoint)))) {
      fs::remove_all(rundir);
      fs::create_directories(rundir);
    }
    std::vector<std::string> env;
    for (char** e = environ; *e; ++e) {
      if (unpin && std::strncmp(*e, "OMP_PROC_BIND=", 14) == 0) continue;
      // A run is a process of its own, not one of mpirun's ranks: without these it starts as a singleton.
      if (std::strncmp(*e, "OMPI_", 5) == 0 || std::strncmp(*e, "PMIX_", 5) == 0) continue;
      env.push_back(*e);
    }
    // One single-threaded run per core: Kokkos' default pinning would put them all on the first core.
    if (unpin) env.push_back("OMP_PROC_BIND=false");
    // The run's command line writing `out`, with the sweep's and the run's overrides.
    const auto command = [&](const std::string& out) {
      std::vector<std::string> argv{
          exe, "run", scene_abs, "--quiet", "--threads", std::to_string(threads), "--out", out};
      for (const auto& s : o.overrides)
        argv.insert(argv.end(), {"--set", s});
      for (const auto& s : plan.sets)
        argv.insert(argv.end(), {"--set", s});
      return argv;
    };

    // The first stage, once: its wall and CPU seconds go to first_stage_time.txt and count with the run's,
    // with its earlier pieces (if it was continued from its checkpoint) counted as the run's are.
    Child stage;
    if (staged && !fs::exists(stage_done)) {
      std::vector<std::string> first = command((rundir / "first_stage.h5").string());
      for (const auto& s : o.first_stage)
        first.insert(first.end(), {"--set", s});
      // Its last step is always checkpointed (cgdem run writes the run's end too).
      first.insert(first.end(), {"--checkpoint-every",
                                 fmt(o.checkpoint_every > 0 ? o.checkpoint_every : o.first_stage_end)});
      const bool continued = fs::exists(stage_checkpoint);
      if (continued) first.insert(first.end(), {"--restart", stage_checkpoint.string()});
      const Pieces earlier = continued ? continue_pieces(rundir, stage_checkpoint, "first_stage_") : Pieces{};
      start_piece(rundir, earlier.last_step, "first_stage_");
      stage = run_child(first, env, rundir, log, continued);
      if (killed(plan, stage.status, " in its first stage")) return false;
      if (WEXITSTATUS(stage.status) != 0) {
        RunRecord r = plan_record(plan, threads);
        r.exit_code = WEXITSTATUS(stage.status);
        r.status = "failed in the first stage (exit " + std::to_string(r.exit_code) + ")";
        finish(r, log);
        return true;
      }
      if (earlier.wall > 0 && stage.wall > 0) {
        stage.cpu += earlier.wall * stage.cpu / stage.wall;
        stage.wall += earlier.wall;
      }
      std::ofstream(rundir / "first_stage_time.txt") << fmt(stage.wall) << " " << fmt(stage.cpu) << "\n";
      std::ofstream(stage_done).flush();
    } else if (staged) {
      std::ifstream(rundir / "first_stage_time.txt") >> stage.wall >> stage.cpu;
    }

    start_piece(rundir, resume ? pieces.last_step : 0);
    std::vector<std::string> argv = command(h5);
    if (o.checkpoint_every > 0) argv.insert(argv.end(), {"--checkpoint-every", fmt(o.checkpoint_every)});
    if (resume) {
      argv.insert(argv.end(), {"--restart", checkpoint.string()});
      std::lock_guard<std::mutex> lock(print);
      std::fprintf(stderr, "sweep: %s continues from its checkpoint at step %ld (piece %d)\n",
                   plan.run.c_str(), pieces.last_step, pieces.count + 1);
    } else if (staged) {
      argv.insert(argv.end(), {"--restart", stage_checkpoint.string()});
    }
    const Child piece = run_child(argv, env, rundir, log, resume || staged);
    if (killed(plan, piece.status, "")) return false;
    RunRecord r = plan_record(plan, threads);
    r.pieces = pieces.count + 1;
    // Earlier pieces count up to their last checkpoint (the work after it was lost and is done again);
    // their CPU time, not measured, is taken at this piece's CPU-to-wall ratio.
    r.wall_time = piece.wall + pieces.wall + stage.wall;
    r.cpu_time = piece.cpu + stage.cpu;
    if (pieces.wall > 0 && piece.wall > 0) r.cpu_time += pieces.wall * piece.cpu / piece.wall;
    r.exit_code = WEXITSTATUS(piece.status);
    r.status = r.exit_code == 0 ? "ok" : "failed (exit " + std::to_string(r.exit_code) + ")";
    if (r.exit_code == 0) {
      try {
        RunOutput out = read_run_output(h5);
        r.particles = out.particles;
        r.steps = resume || staged ? out.last_step : out.steps; // both stages: steps from the start
        r.time_step = out.time_step;
        r.values = out.final_values;
        r.particle_steps_per_s = r.wall_time > 0 ? double(r.steps) * r.particles / r.wall_time : 0;
        r.engine_particle_steps_per_s = engine_rate_from_log(log);
        for (const auto& a : analyses)
          if (a->is_distribution())
            r.samples[a->name()] = quantile_samples(a->samples(out.last), kMaxSamples);
      } catch (const std::exception& e) {
        r.status = std::string("failed (unreadable result: ") + e.what() + ")";
        r.exit_code = -1;
      }
    }
    finish(r, log);
    return true;
  }
};

// ---- tables and plots ----

struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> text; // as written to the CSV
  std::vector<std::vector<double>> numbers;   // NaN for text columns
  std::vector<bool> is_text;
};

Table make_table(const std::vector<SweepRow>& rows, const RunRecord& ref) {
  Table t;
  t.columns = {"run",
               "law",
               "k",
               "status",
               "exit_code",
               "particles",
               "mass_kg",
               "mass_ratio",
               "steps",
               "time_step",
               "threads",
               "wall_time_s",
               "cpu_time_s",
               "particle_steps_per_s",
               "engine_particle_steps_per_s",
               "speedup",
               "speedup_cpu"};
  // A run's value named like one of the record's own columns (an outlet's `particles`, the count the
  // record holds already) would give the CSV and the HDF5 group two columns of one name.
  std::vector<std::string> metrics, dists;
  for (const auto& kv : ref.values)
    if (std::find(t.columns.begin(), t.columns.end(), kv.first) == t.columns.end())
      metrics.push_back(kv.first);
  for (const auto& kv : ref.samples)
    dists.push_back(kv.first);
  for (const auto& m : metrics)
    t.columns.push_back(m);
  for (const auto& m : metrics)
    t.columns.push_back("err_" + m);
  for (const auto& m : metrics)
    t.columns.push_back("err_mass_matched_" + m);
  for (const auto& d : dists)
    t.columns.insert(t.columns.end(), {"w1_" + d, "ks_" + d});
  for (const auto& c : t.columns)
    t.is_text.push_back(c == "run" || c == "law" || c == "status");
  const double nan = std::nan("");
  for (const auto& row : rows) {
    const RunRecord& r = row.record;
    std::vector<double> v{nan,
                          nan,
                          r.k,
                          nan,
                          double(r.exit_code),
                          double(r.particles),
                          r.mass > 0 ? r.mass : nan,
                          r.mass > 0 && ref.mass > 0 ? r.mass / ref.mass : nan,
                          double(r.steps),
                          r.time_step,
                          double(r.threads),
                          r.wall_time,
                          r.cpu_time,
                          r.particle_steps_per_s,
                          r.engine_particle_steps_per_s,
                          row.speedup,
                          row.speedup_cpu};
    auto get = [&](const std::map<std::string, double>& m, const std::string& k) {
      auto it = m.find(k);
      return it == m.end() ? nan : it->second;
    };
    for (const auto& m : metrics)
      v.push_back(get(r.values, m));
    for (const auto& m : metrics)
      v.push_back(get(row.error, m));
    for (const auto& m : metrics)
      v.push_back(get(row.mass_matched, m));
    for (const auto& d : dists)
      v.insert(v.end(), {get(row.w1, d), get(row.ks, d)});
    std::vector<std::string> s;
    for (std::size_t c = 0; c < v.size(); ++c) {
      if (c == 0)
        s.push_back(r.run);
      else if (c == 1)
        s.push_back(r.law);
      else if (c == 3)
        s.push_back(row.status);
      else
        s.push_back(std::isnan(v[c]) ? "" : fmt(v[c]));
    }
    t.numbers.push_back(v);
    t.text.push_back(s);
  }
  return t;
}

void write_csv(const std::string& path, const Table& t) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    for (std::size_t c = 0; c < t.columns.size(); ++c)
      out << (c ? "," : "") << t.columns[c];
    out << "\n";
    for (const auto& row : t.text) {
      for (std::size_t c = 0; c < row.size(); ++c) {
        std::string cell = row[c];
        if (cell.find(',') != std::string::npos) cell = "\"" + cell + "\"";
        out << (c ? "," : "") << cell;
      }
      out << "\n";
    }
  }
  fs::rename(tmp, path);
}

void write_h5(const std::string& path, const Table& t, const SweepOptions& o, const std::string& policy) {
  std::lock_guard<std::mutex> lock(hdf5_mutex());
  const std::string tmp = path + ".tmp";
  {
    H5 file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
    if (file < 0) throw std::runtime_error("cannot create " + tmp);
    auto str_attr = [&](const char* name, const std::string& value) {
      H5 type(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(type, std::max<std::size_t>(1, value.size()));
      H5 space(H5Screate(H5S_SCALAR), H5Sclose);
      H5 a(H5Acreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
      H5Awrite(a, type, value.c_str());
    };
    str_attr("scene", o.scene);
    str_attr("policy", policy);
    std::string laws;
    for (const auto& l : o.laws)
      laws += (laws.empty() ? "" : ",") + l;
    str_attr("laws", laws);
    H5 runs(H5Gcreate2(file, "runs", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    const hsize_t n = t.text.size();
    for (std::size_t c = 0; c < t.columns.size(); ++c) {
      H5 space(H5Screate_simple(1, &n, nullptr), H5Sclose);
      if (t.is_text[c]) {
        std::size_t width = 1;
        for (const auto& row : t.text)
          width = std::max(width, row[c].size());
        std::vector<char> buf(n * width, 0);
        for (hsize_t r = 0; r < n; ++r)
          std::memcpy(&buf[r * width], t.text[r][c].data(), t.text[r][c].size());
        H5 type(H5Tcopy(H5T_C_S1), H5Tclose);
        H5Tset_size(type, width);
        H5 ds(H5Dcreate2(runs, t.columns[c].c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              H5Dclose);
        if (n) H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data());
      } else {
        std::vector<double> col;
        for (const auto& row : t.numbers)
          col.push_back(row[c]);
        H5 ds(H5Dcreate2(runs, t.columns[c].c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT,
                         H5P_DEFAULT),
              H5Dclose);
        if (n) H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, col.data());
      }
    }
  }
  fs::rename(tmp, path);
}

} // namespace

// ---- records ----

void write_record(const std::string& path, const RunRecord& r) {
  std::ostringstream s;
  s << "run " << r.run << "\nlaw " << r.law << "\nk " << fmt(r.k) << "\nstatus " << r.status << "\nexit_code "
    << r.exit_code << "\nthreads " << r.threads << "\nseed " << r.seed << "\npieces " << r.pieces
    << "\nparticles " << r.particles << "\nmass_kg " << fmt(r.mass) << "\nsteps " << r.steps << "\ntime_step "
    << fmt(r.time_step) << "\nwall_time_s " << fmt(r.wall_time) << "\ncpu_time_s " << fmt(r.cpu_time)
    << "\nparticle_steps_per_s " << fmt(r.particle_steps_per_s) << "\nengine_particle_steps_per_s "
    << fmt(r.engine_particle_steps_per_s) << "\n";
  for (const auto& kv : r.values)
    s << "value " << kv.first << " " << fmt(kv.second) << "\n";
  for (const auto& kv : r.samples) {
    s << "samples " << kv.first;
    for (double x : kv.second)
      s << " " << fmt(x);
    s << "\n";
  }
  const std::string text = s.str();
  const std::string tmp = path + ".tmp";
  fs::create_directories(fs::path(path).parent_path());
  const int fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) throw std::runtime_error("cannot write " + tmp);
  std::size_t off = 0;
  while (off < text.size()) {
    const ssize_t w = write(fd, text.data() + off, text.size() - off);
    if (w <= 0) {
      close(fd);
      throw std::runtime_error("cannot write " + tmp);
    }
    off += static_cast<std::size_t>(w);
  }
  fsync(fd);
  close(fd);
  fs::rename(tmp, path); // atomic: the record is either absent or complete
}

namespace {

// A recorded number; strtod, unlike operator>>, reads back the "nan" and "inf" that fmt writes.
double number(const std::string& s) {
  char* end = nullptr;
  const double x = std::strtod(s.c_str(), &end);
  return end == s.c_str() ? std::nan("") : x;
}

} // namespace

RunRecord read_record(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read record " + path);
  RunRecord r;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    auto rest = [&]() {
      std::string v;
      std::getline(ls, v);
      return v.empty() ? v : v.substr(1);
    };
    if (key == "run")
      r.run = rest();
    else if (key == "law")
      r.law = rest();
    else if (key == "status")
      r.status = rest();
    else if (key == "k")
      ls >> r.k;
    else if (key == "exit_code")
      ls >> r.exit_code;
    else if (key == "threads")
      ls >> r.threads;
    else if (key == "seed")
      ls >> r.seed;
    else if (key == "pieces")
      ls >> r.pieces;
    else if (key == "particles")
      ls >> r.particles;
    else if (key == "mass_kg")
      ls >> r.mass;
    else if (key == "steps")
      ls >> r.steps;
    else if (key == "time_step")
      ls >> r.time_step;
    else if (key == "wall_time_s")
      ls >> r.wall_time;
    else if (key == "cpu_time_s")
      ls >> r.cpu_time;
    else if (key == "particle_steps_per_s")
      ls >> r.particle_steps_per_s;
    else if (key == "engine_particle_steps_per_s")
      ls >> r.engine_particle_steps_per_s;
    else if (key == "value") {
      std::string name, v;
      ls >> name >> v;
      r.values[name] = number(v);
    } else if (key == "samples") {
      std::string name, x;
      ls >> name;
      auto& v = r.samples[name];
      while (ls >> x)
        v.push_back(number(x));
    }
  }
  if (r.run.empty()) throw std::runtime_error("record " + path + " names no run");
  return r;
}

double mass_matched_error(double x, double x_ref, double mass, double ref_mass, double p) {
  if (!(mass > 0) || !(ref_mass > 0)) return std::nan("");
  const double corrected = x_ref * std::pow(mass / ref_mass, p);
  const double d = std::abs(x - corrected);
  return corrected != 0 ? d / std::abs(corrected) : d;
}

namespace {

// "" when the run succeeded, else why it failed: its exit status, or the main figures (values, or the
// samples of a distribution) it lacks or has as nan.
std::string failure(const RunRecord& r, const SweepAnalyses& a) {
  if (r.exit_code != 0)
    return r.status.empty() ? "failed (exit " + std::to_string(r.exit_code) + ")" : r.status;
  std::string missing, nan;
  for (const auto& m : a.main) {
    auto it = r.values.find(m);
    if (it == r.values.end())
      missing += (missing.empty() ? "" : " ") + m;
    else if (!std::isfinite(it->second))
      nan += (nan.empty() ? "" : " ") + m;
  }
  for (const auto& d : a.distributions) {
    auto it = r.samples.find(d);
    if (it == r.samples.end() || it->second.empty())
      missing += (missing.empty() ? "" : " ") + d;
    else if (!std::all_of(it->second.begin(), it->second.end(), [](double x) { return std::isfinite(x); }))
      nan += (nan.empty() ? "" : " ") + d;
  }
  if (missing.empty() && nan.empty()) return "";
  std::string why;
  if (!nan.empty()) why = "nan: " + nan;
  if (!missing.empty()) why += (why.empty() ? "" : "; ") + std::string("missing: ") + missing;
  return "failed (" + why + ")";
}

} // namespace

std::vector<SweepRow> compare_runs(const std::vector<RunRecord>& runs, const RunRecord& ref,
                                   const SweepAnalyses& analyses) {
  std::vector<SweepRow> rows;
  for (const auto& r : runs) {
    SweepRow row;
    row.record = r;
    const std::string why = failure(r, analyses);
    row.ok = why.empty();
    row.status = row.ok ? (r.status.empty() ? "ok" : r.status) : why;
    const bool ok = r.exit_code == 0 && ref.exit_code == 0;
    row.speedup = ok && r.wall_time > 0 ? ref.wall_time / r.wall_time : std::nan("");
    row.speedup_cpu = ok && r.cpu_time > 0 && ref.cpu_time > 0 ? ref.cpu_time / r.cpu_time : std::nan("");
    if (ok) {
      for (const auto& kv : ref.values) {
        auto it = r.values.find(kv.first);
        if (it == r.values.end() || !std::isfinite(it->second) || !std::isfinite(kv.second)) continue;
        const double d = std::abs(it->second - kv.second);
        row.error[kv.first] = kv.second != 0 ? d / std::abs(kv.second) : d;
        auto p = analyses.mass_exponent.find(kv.first);
        if (p == analyses.mass_exponent.end()) continue;
        const double e = mass_matched_error(it->second, kv.second, r.mass, ref.mass, p->second);
        if (std::isfinite(e)) row.mass_matched[kv.first] = e;
      }
      for (const auto& kv : ref.samples) {
        auto it = r.samples.find(kv.first);
        if (it == r.samples.end() || it->second.empty() || kv.second.empty()) continue;
        row.w1[kv.first] = wasserstein1(it->second, kv.second);
        row.ks[kv.first] = ks_distance(it->second, kv.second);
      }
    }
    rows.push_back(row);
  }
  return rows;
}

// ---- command line ----

SweepOptions parse_sweep_options(const std::vector<std::string>& args) {
  SweepOptions o;
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& a = args[k];
    const std::string name = a.substr(0, a.find('='));
    auto value = [&]() -> std::string {
      const auto eq = a.find('=');
      if (a.rfind("--", 0) == 0 && eq != std::string::npos) return a.substr(eq + 1);
      if (k + 1 >= args.size()) throw CliError("option " + a + " needs a value (see --help)");
      return args[++k];
    };
    if (name == "--laws")
      o.laws = split(value(), ',');
    else if (name == "--k") {
      for (const auto& s : split(value(), ',')) {
        char* end = nullptr;
        const double x = std::strtod(s.c_str(), &end);
        if (end == s.c_str() || *end || !(x >= 1))
          throw CliError("--k expects scale factors >= 1 separated by commas, got '" + s + "'");
        o.factors.push_back(x);
      }
    } else if (name == "--set")
      o.overrides.push_back(value());
    else if (name == "--coarse-set") {
      const std::string v = value();
      const auto eq = v.find('=');
      if (eq == 0 || eq == std::string::npos || eq + 1 == v.size() || v.find('.') < eq)
        throw CliError("--coarse-set expects key=value of the coarse_grain map, e.g. surface_energy_power=1, "
                       "got '" +
                       v + "'");
      o.coarse_sets.push_back(v);
    } else if (name == "--out")
      o.out = value();
    else if (name == "--threads") {
      const std::string v = value();
      char* end = nullptr;
      const long t = std::strtol(v.c_str(), &end, 10);
      if (end == v.c_str() || *end || t < 1)
        throw CliError("--threads expects a positive integer, got '" + v + "'");
      o.threads = static_cast<int>(t);
    } else if (name == "--policy") {
      o.policy = value();
      if (o.policy != "auto" && o.policy != "serial" && o.policy != "parallel")
        throw CliError("--policy expects auto, serial or parallel, got '" + o.policy + "'");
    } else if (name == "--seeds" || name == "--reference-seeds") {
      auto& list = name == "--seeds" ? o.seeds : o.reference_seeds;
      for (const auto& v : split(value(), ',')) {
        char* end = nullptr;
        const long x = std::strtol(v.c_str(), &end, 10);
        if (end == v.c_str() || *end || x < 0)
          throw CliError(name + " expects non-negative integer seeds separated by commas, got '" + v + "'");
        if (std::find(list.begin(), list.end(), x) != list.end())
          throw CliError(name + " lists seed " + v + " twice");
        list.push_back(x);
      }
    } else if (name == "--checkpoint-every") {
      const std::string v = value();
      char* end = nullptr;
      o.checkpoint_every = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end || !(o.checkpoint_every > 0))
        throw CliError("--checkpoint-every expects a positive number of simulated seconds, got '" + v + "'");
    } else if (name == "--first-stage") {
      o.first_stage.push_back(value());
    } else if (name == "--quiet" || name == "-q")
      o.quiet = true;
    else if (name == "--no-plots")
      o.plots = false;
    else if (!a.empty() && a[0] == '-')
      throw CliError("unknown option '" + a + "' (see --help)");
    else if (o.scene.empty())
      o.scene = a;
    else
      throw CliError("unexpected argument '" + a + "': one scene per sweep");
  }
  if (o.scene.empty()) throw CliError("no scene file given (see --help)");
  if (o.laws.empty()) throw CliError("--laws is required, e.g. --laws chen_elliott,hu_method1");
  if (o.factors.empty()) throw CliError("--k is required, e.g. --k 1,2,3,4");
  if (!o.reference_seeds.empty() && o.seeds.empty())
    throw CliError("--reference-seeds needs --seeds (the seeds of the coarse-grained runs)");
  if (o.reference_seeds.empty()) o.reference_seeds = o.seeds;
  std::sort(o.factors.begin(), o.factors.end());
  o.factors.erase(std::unique(o.factors.begin(), o.factors.end()), o.factors.end());
  return o;
}

const char* sweep_help() {
  return R"(Usage: cgdem sweep SCENE.yaml --laws L1,L2,... --k 1,2,3,4 [options]

Runs SCENE.yaml once with original-size particles (the reference, k = 1) and once per coarse-graining law
and scale factor k > 1 (groups.*.coarse_grain = {law, factor} on every group, and each generated group's
count divided by k^3 so that the same mass of powder is simulated). Each run is a separate 'cgdem run'
process; its wall time, particle-steps per second, step and particle counts and the final values of the
scene's analyses are recorded. Speed-up = reference wall time / run wall time; error = relative
difference of each analysis value from the reference (W1 and KS distances for velocity distributions);
mass-matched error = the same against the reference scaled to the run's particle mass by the value's
mass exponent (docs/sweeps.md). A run that exits non-zero or lacks a finite main figure is listed as
failed in sweep.csv (status, exit_code) and left out of the plots.

Writes DIR/sweep.csv, DIR/sweep.h5 (/runs/<column>), DIR/speedup.png, DIR/error.png, one record per run
in DIR/records/ and each run's HDF5 file and log in DIR/runs/<run>/. Started again, the sweep skips every
run whose record exists (records are written atomically when a run ends).

Options:
  --laws L1,L2,...       coarse-graining laws (see docs/scene_format.md, groups.coarse_grain.law)
  --k 1,2,3,4            scale factors; the k = 1 reference is always run (law none)
  --set key.path=value   scene override applied to every run (repeatable)
  --out DIR              output directory (default: sweep)
  --threads N            cores to use (default: all)
  --policy P             serial: one run at a time on N threads; parallel: N single-threaded runs at a
                         time (oneTBB task group); auto (default): the faster on the measured small
                         scenes, parallel (docs/sweeps.md)
  --seeds 1,2,3          run every case once per seed of the initial packing (each group's
                         placement.seed = seed + 1000 x group index; runs named <case>_s<seed>) and write
                         DIR/summary.csv: per case the mean and standard deviation over its seeds, the
                         error of the mean against the reference's mean, the seed-to-seed scatter of
                         that difference and whether the error is within it
  --reference-seeds 1,2  the reference's seeds when they differ from --seeds (it is the costly run)
  --coarse-set key=value an option of the law in every coarse-grained run (repeatable): set in each group's
                         coarse_grain map after {law, factor}, e.g. --coarse-set surface_energy_power=1
                         (docs/scene_format.md, groups.coarse_grain); the reference runs without it
  --checkpoint-every T   each run writes a checkpoint every T simulated seconds; started again, the sweep
                         continues an unfinished run from its checkpoint instead of from the start (for
                         runs longer than a sitting: kill the sweep, start the same command later)
  --first-stage key=value
                         an override of a first stage (repeatable): every run first runs the scene with
                         these overrides to their time.end (first_stage.h5 in its directory), then continues
                         from that stage's last step with the scene as given (`cgdem run --restart`), so a
                         protocol can change what is not particle state between stages: friction, walls,
                         outlets, the domain's periodicity. Times and rates count both stages; the
                         analyses are those of the scene as given
  --no-plots             skip the PNG plots
  --quiet                no line per finished run

Examples:
  cgdem sweep sweeps/tiny_pile.yaml --laws chen_elliott,bond --k 1,2,3 --out tiny_sweep
  cgdem sweep sweeps/chen_repose.yaml --laws chen_elliott --k 2 --seeds 1,2,3 --reference-seeds 1,2 \
      --checkpoint-every 0.1 --out repose
  cgdem sweep sweeps/hu_compression_paper.yaml --laws hu_method1 --k 2,4 --seeds 1,2,3 --first-stage \
      materials.glass.friction=0.01 --first-stage time.end=0.5 --first-stage 'outlets.0.point=[0,0,0.1299]'
      (Hu's compression: poured with friction 0.01, then friction 0.3, the cut and the piston)
  mpirun -np 4 cgdem sweep sweeps/tiny_pile.yaml --laws bond --k 1,2 --seeds 1,2 --out tiny_sweep
      (under mpirun each rank runs every 4th run on its cores / ranks threads; rank 0 writes the tables)
)";
}

int sweep_command(const std::vector<std::string>& args) {
  for (const auto& a : args)
    if (a == "--help" || a == "-h") {
      std::cout << sweep_help();
      return 0;
    }
  // Under mpirun each rank runs its share of the runs (every ranks-th, from its rank on); rank 0 then
  // compares them all from their records and alone prints and writes the tables.
  const int rank = parallel::world_rank(), ranks = parallel::world_size();
  if (rank != 0) std::freopen("/dev/null", "w", stderr);
  Sweep s;
  try {
    s.o = parse_sweep_options(args);
  } catch (const CliError& e) {
    std::cerr << "cgdem sweep: " << e.what() << "\n";
    return exit_bad_input;
  }
  SweepOptions& o = s.o;
  if (const std::string problem = output_dir_problem(o.out); !problem.empty()) {
    std::cerr << "cgdem sweep: " << problem << "\n";
    return exit_bad_input;
  }
  std::vector<RunPlan> plans;
  try {
    s.scene = parse_scene_file(o.scene, o.overrides);
    s.analyses = make_analyses(s.scene);
    if (!o.first_stage.empty()) { // checked here: a bad key of the first stage stops the sweep before any run
      std::vector<std::string> staged = o.overrides;
      staged.insert(staged.end(), o.first_stage.begin(), o.first_stage.end());
      o.first_stage_end = parse_scene_file(o.scene, staged).time.end;
      if (!(o.first_stage_end < s.scene.time.end))
        throw std::runtime_error("the first stage ends at " + fmt(o.first_stage_end) +
                                 " s, not before the scene's time.end (" + fmt(s.scene.time.end) +
                                 " s): give it its own end, --first-stage time.end=T");
    }
    for (std::size_t g = 0; g < s.scene.groups.size(); ++g)
      if (s.scene.groups[g].placement.kind == "file")
        throw SceneError(
            scene_error_message(s.scene.source_file, "groups." + std::to_string(g) + ".placement",
                                "a sweep scales the particle count by k^-3, which a file group cannot do",
                                "generate the particles (lattice, random_box, random_cylinder)"));
    auto plan = [&](const std::string& law, double k, long seed) {
      RunPlan p;
      p.law = law;
      p.k = k;
      p.seed = seed;
      p.run =
          (k == 1 ? "reference" : law + "_k" + k_name(k)) + (seed >= 0 ? "_s" + std::to_string(seed) : "");
      for (std::size_t g = 0; g < s.scene.groups.size(); ++g) {
        const std::string key = "groups." + std::to_string(g);
        p.sets.push_back(key + ".coarse_grain={law: " + law + ", factor: " + fmt(k) + "}");
        if (k != 1)
          for (const auto& c : o.coarse_sets)
            p.sets.push_back(key + ".coarse_grain." + c);
        const long count = std::max(1L, std::lround(s.scene.groups[g].count / (k * k * k)));
        p.sets.push_back(key + ".count=" + std::to_string(count));
        if (seed >= 0) p.sets.push_back(key + ".placement.seed=" + std::to_string(seed + 1000 * long(g)));
      }
      return p; // checked below, with every other run, before anything runs
    };
    const std::vector<long> no_seed{-1};
    for (long seed : o.reference_seeds.empty() ? no_seed : o.reference_seeds)
      plans.push_back(plan("none", 1, seed));
    for (const auto& law : o.laws)
      for (double k : o.factors)
        if (k != 1)
          for (long seed : o.seeds.empty() ? no_seed : o.seeds)
            plans.push_back(plan(law, k, seed));
  } catch (const SceneError& e) {
    std::cerr << "cgdem: " << e.what() << "\n";
    return exit_bad_input;
  } catch (const std::exception& e) {
    std::cerr << "cgdem: " << o.scene << ": " << e.what() << "\n";
    return exit_bad_input;
  }
  // Every run checked as `cgdem check` would check it before the first one starts: a coarse run that would
  // fail (a periodic axis shorter than 3 cells at its size, a step above its limit) stops the sweep here.
  // The runs' warnings are shown, and a run whose particles do not weigh what the reference's weigh (a
  // count that k^3 does not divide, a small polydisperse sample) is named: part of its error is sampling.
  {
    KokkosSession kokkos(1);
    for (auto& p : plans) {
      std::vector<std::string> all = o.overrides;
      all.insert(all.end(), p.sets.begin(), p.sets.end());
      try {
        const RunCheck c = check_run(o.scene, all);
        p.particles = c.particles;
        p.mass = c.mass;
        for (const auto& w : c.warnings)
          std::fprintf(stderr, "cgdem sweep: %s: %s\n", p.run.c_str(), w.c_str());
        if (!o.first_stage.empty()) {
          all.insert(all.end(), o.first_stage.begin(), o.first_stage.end());
          for (const auto& w : check_run(o.scene, all).warnings) // those the second stage has not given
            if (std::find(c.warnings.begin(), c.warnings.end(), w) == c.warnings.end())
              std::fprintf(stderr, "cgdem sweep: %s, first stage: %s\n", p.run.c_str(), w.c_str());
        }
      } catch (const std::exception& e) {
        std::fprintf(stderr, "cgdem sweep: run %s (law %s, k = %s) would fail, nothing was run: %s\n",
                     p.run.c_str(), p.law.c_str(), fmt(p.k).c_str(), e.what());
        return exit_bad_input;
      }
    }
    const double ref_mass = plans.front().mass;
    for (const auto& p : plans)
      if (ref_mass > 0 && std::fabs(p.mass / ref_mass - 1) > 0.01)
        std::fprintf(stderr,
                     "cgdem sweep: %s: its %ld particles weigh %+.1f %% against the reference's %ld: part of "
                     "its error is sampling (mass_ratio in sweep.csv)\n",
                     p.run.c_str(), p.particles, 100 * (p.mass / ref_mass - 1), plans.front().particles);
  }

  const int threads =
      o.threads > 0 ? o.threads : std::max(1, int(std::thread::hardware_concurrency()) / std::max(1, ranks));
  const std::string policy = o.policy == "auto" ? kAutoPolicy : o.policy;
  s.dir = fs::absolute(o.out);
  s.exe = self_exe();
  s.scene_abs = fs::absolute(o.scene).string();
  {
    std::error_code ec;
    fs::create_directories(s.dir / "records", ec);
    if (!ec) fs::create_directories(s.dir / "runs", ec);
    if (ec) {
      std::cerr << "cgdem sweep: cannot create " << s.dir.string() << ": " << ec.message() << "\n";
      return exit_write_failed;
    }
  }

  std::vector<RunPlan> pending;
  for (std::size_t k = 0; k < plans.size(); ++k) {
    const RunPlan& p = plans[k];
    if (int(k % std::size_t(ranks)) != rank) continue; // another rank's
    if (fs::exists(s.record_path(p.run))) {
      if (!o.quiet)
        std::fprintf(stderr, "skip %s: record exists (%s)\n", p.run.c_str(), s.record_path(p.run).c_str());
    } else {
      pending.push_back(p);
    }
  }
  s.total = static_cast<int>(pending.size());
  if (!o.quiet)
    std::fprintf(stderr, "cgdem sweep: %zu runs (%zu to do%s), policy %s on %d threads, results in %s\n",
                 plans.size(), pending.size(),
                 ranks > 1 ? (" on rank 0 of " + std::to_string(ranks) + ", the others alike").c_str() : "",
                 policy.c_str(), threads, s.dir.c_str());
  if (!o.quiet)
    for (const auto& c : o.coarse_sets) // not in the runs' names: said once here
      std::fprintf(stderr, "cgdem sweep: the coarse-grained runs with coarse_grain.%s\n", c.c_str());
  const auto start = std::chrono::steady_clock::now();
  std::atomic<bool> interrupted{false};
  if (policy == "serial") {
    for (const auto& p : pending)
      if (!s.execute(p, threads, false)) interrupted = true;
  } else {
    // One worker per thread, each taking the next run in plan order: the references (the longest runs)
    // start first, and the order does not depend on how the task scheduler picks tasks.
    std::atomic<std::size_t> next{0};
    tbb::task_arena arena(threads);
    arena.execute([&] {
      tbb::task_group group;
      for (int w = 0; w < threads; ++w)
        group.run([&] {
          for (std::size_t i = next++; i < pending.size(); i = next++)
            if (!s.execute(pending[i], 1, true)) interrupted = true;
        });
      group.wait();
    });
  }
  if (parallel::max_over_ranks(interrupted ? 1 : 0)) {
    std::fprintf(stderr, "cgdem sweep: some runs did not finish; start the sweep again to complete them\n");
    return 1;
  }
  if (rank != 0) return 0;

  // Everything below comes from the records alone.
  // With several reference seeds every run is compared with their mean.
  std::vector<RunRecord> records, reference_runs;
  for (const auto& p : plans) {
    records.push_back(read_record(s.record_path(p.run).string()));
    if (p.law == "none") reference_runs.push_back(records.back());
  }
  const RunRecord reference =
      reference_runs.size() == 1 ? reference_runs.front() : mean_record(reference_runs, "reference");
  SweepAnalyses compared;
  for (const auto& a : s.analyses)
    (a->is_distribution() ? compared.distributions : compared.main).push_back(a->metric());
  compared.mass_exponent = mass_exponents(s.analyses);
  const auto rows = compare_runs(records, reference, compared);
  const Table table = make_table(rows, reference);
  const std::string csv = (s.dir / "sweep.csv").string();
  write_csv(csv, table);
  std::vector<CaseSummary> cases;
  if (!o.seeds.empty()) {
    cases = summarize_cases(records, compared.main);
    write_summary_csv((s.dir / "summary.csv").string(), cases, compared.main);
  }
  write_h5((s.dir / "sweep.h5").string(), table, o, policy);
  std::string mains;
  for (const auto& a : s.analyses)
    mains += (mains.empty() ? "" : ",") + (a->is_distribution() ? a->name() : a->metric());
  if (o.plots) {
    const std::string cmd = "/usr/bin/python3 '" CGDEM_SOURCE_DIR "/sweeps/plot_sweep.py' '" + csv + "' '" +
                            s.dir.string() + "' --metrics '" + mains + "'";
    if (std::system(cmd.c_str()) != 0)
      std::fprintf(stderr, "cgdem sweep: the plots failed (%s); the tables are written\n", cmd.c_str());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::string failed;
  for (const auto& r : rows)
    if (!r.ok) failed += (failed.empty() ? "" : ", ") + r.record.run;
  if (!o.quiet) {
    std::fprintf(stderr, "done: %d runs in %.1f s; wrote %s, sweep.h5 and the plots in %s\n", s.total, wall,
                 csv.c_str(), s.dir.c_str());
    for (const auto& r : rows) {
      if (!r.ok) {
        std::fprintf(stderr, "  %-24s %s: left out of the plots\n", r.record.run.c_str(), r.status.c_str());
        continue;
      }
      std::fprintf(stderr, "  %-24s speed-up %7.2f (CPU time %7.2f)", r.record.run.c_str(), r.speedup,
                   r.speedup_cpu);
      for (const auto& a : s.analyses) {
        auto e = r.error.find(a->metric());
        auto mm = r.mass_matched.find(a->metric());
        auto ks = r.ks.find(a->name());
        if (ks != r.ks.end())
          std::fprintf(stderr, "  %s KS %.3f", a->name().c_str(), ks->second);
        else if (e != r.error.end()) {
          std::fprintf(stderr, "  %s err %.3f", a->metric().c_str(), e->second);
          // Shown when the masses differ enough to change the figure.
          if (mm != r.mass_matched.end() && std::fabs(mm->second - e->second) >= 5e-4)
            std::fprintf(stderr, " (mass-matched %.3f)", mm->second);
        }
      }
      std::fprintf(stderr, "  %s\n", r.status.c_str());
    }
  }
  if (!o.quiet && !cases.empty()) {
    std::fprintf(stderr,
                 "over the seeds (summary.csv): mean +- sd; error of the mean against the reference's, "
                 "and the seed-to-seed scatter of that difference\n");
    for (const auto& c : cases) {
      std::fprintf(stderr, "  %-16s k %-4s %d seeds  speed-up %7.2f (CPU %7.2f)", c.law.c_str(),
                   k_name(c.k).c_str(), c.seeds, c.speedup, c.speedup_cpu);
      for (const auto& v : compared.main) {
        const SampleStats& st = c.values.at(v);
        std::fprintf(stderr, "  %s %.4g +- %.2g", v.c_str(), st.mean, st.sd);
        if (c.law != "none")
          std::fprintf(stderr, " (err %+.3f, scatter %.3f%s)", c.error.at(v), c.scatter.at(v),
                       std::isnan(c.within.at(v)) ? ""
                       : c.within.at(v) > 0       ? ", within"
                                                  : ", beyond");
      }
      std::fprintf(stderr, "\n");
    }
  }
  if (!failed.empty()) {
    std::fprintf(stderr, "cgdem sweep: failed: %s (see status and exit_code in %s)\n", failed.c_str(),
                 csv.c_str());
    return 1;
  }
  return 0;
}

} // namespace cgdem
