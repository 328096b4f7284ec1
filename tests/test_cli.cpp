// The cgdem executable end to end: bad input (exit 2, one line, no output file), --set, restart
// bitwise, SIGKILL leaves readable frames, bitwise identical trajectories on 1 and 2 OpenMP threads and
// Serial, and the HDF5/XDMF contract of a real run.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <thread>
#include "core/particle_store.hpp"
#include "drivers/kokkos_session.hpp"
#include "tests/cli_support.hpp"

using namespace cgdem::testing;

namespace {

// A small, real scene: 500 beads dropped on a floor in a periodic box (about 2 s of CPU).
const char* drop_scene = R"(domain:
  lo: [0, 0, 0]
  hi: [0.01, 0.01, 0.03]
  periodic: [true, true, false]
gravity: [0, 0, -9.81]
materials:
  beads:
    density: 2500
    youngs_modulus: 5.0e6
    poisson_ratio: 0.3
    restitution: 0.7
    friction: 0.4
contact:
  normal: hertz
groups:
  - name: lattice
    material: beads
    count: 500
    size: {radius: 0.0005}
    placement:
      type: lattice
      lo: [0, 0, 0.001]
      hi: [0.01, 0.01, 0.02]
      spacing: 0.00105
    velocity: [0, 0, -0.3]
walls:
  - name: floor
    type: plane
    material: beads
    point: [0, 0, 0]
    normal: [0, 0, 1]
time:
  end: 0.04
  step: 5.0e-6
output:
  every: 0.01
  file: drop.h5
)";

} // namespace

TEST_F(CliTest, BadInputGivesOneLineExitTwoAndNoOutput) {
  write("base.yaml", drop_scene);
  write("overlap.csv", "id,x,y,z,radius\n1,0.005,0.005,0.005,0.0005\n2,0.005,0.005,0.0058,0.0005\n");
  struct Case {
    const char* what;
    std::string set;    // --set override applied to the good scene
    const char* expect; // text the message must contain
  };
  const std::vector<Case> cases = {
      {"unknown key", "--set materials.beads.youngs_modulos=5e6", "did you mean 'youngs_modulus'"},
      {"wrong type", "--set materials.beads.density=heavy", "materials.beads.density"},
      {"negative radius", "--set groups.0.size.radius=-0.001", "radius"},
      {"zero density", "--set materials.beads.density=0", "density"},
      {"poisson ratio", "--set materials.beads.poisson_ratio=0.7", "poisson_ratio"},
      {"restitution", "--set materials.beads.restitution=1.5", "restitution"},
      {"particle outside the domain", "--set groups.0.placement.hi=[0.01,0.01,0.05]", "domain"},
      {"initial overlaps",
       "--set 'groups.0={name: g, material: beads, placement: {type: file, file: overlap.csv}}'", "overlap"},
      {"unreadable particle file",
       "--set 'groups.0={name: g, material: beads, placement: {type: file, file: missing.csv}}'",
       "missing.csv"},
      {"time step above the stable limit", "--set time.step=1e-4", "time.step"},
  };
  for (const Case& c : cases) {
    const Result r = cgdem("run base.yaml --out bad.h5 " + c.set);
    EXPECT_EQ(r.code, 2) << c.what << ": " << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.what << ": " << r.err;
    EXPECT_NE(r.err.find("base.yaml"), std::string::npos) << c.what << " names the file: " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.what << " is one line: " << r.err;
    EXPECT_FALSE(fs::exists(dir / "bad.h5")) << c.what;
    EXPECT_FALSE(fs::exists(dir / "bad.xdmf")) << c.what;
  }
  // An output directory that does not exist: a one-line error before any work, not an abort.
  const Result nodir = cgdem("run base.yaml --out no_such_dir/out.h5");
  EXPECT_EQ(nodir.code, 2) << nodir.err;
  EXPECT_NE(nodir.err.find("no_such_dir"), std::string::npos) << nodir.err;
  EXPECT_NE(nodir.err.find("does not exist"), std::string::npos) << nodir.err;
  EXPECT_EQ(std::count(nodir.err.begin(), nodir.err.end(), '\n'), 1) << nodir.err;
  EXPECT_FALSE(fs::exists(dir / "no_such_dir"));
  // Missing required key: remove the materials' density by rewriting the scene.
  std::string text = drop_scene;
  text.erase(text.find("    density: 2500\n"), std::string("    density: 2500\n").size());
  write("nodensity.yaml", text);
  const Result r = cgdem("run nodensity.yaml --out bad.h5");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("density"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "bad.h5"));
}

TEST_F(CliTest, CheckReportsTheMemoryTheEngineHolds) {
  // Measured from an engine built as 'run' builds it: at least the particle store per particle, and not an
  // estimate that ignores the particle count.
  write("base.yaml", drop_scene);
  const std::regex memory("memory +[0-9.]+ [KMG]?i?B in the engine \\(([0-9]+) B per particle");
  std::smatch m;
  const Result r = cgdem("check base.yaml --set groups.0.count=400");
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(std::regex_search(r.out, m, memory)) << r.out;
  EXPECT_GE(std::stod(m[1]), double(cgdem::ParticleStore<Kokkos::HostSpace>::bytes_per_particle())) << r.out;
  EXPECT_LT(std::stod(m[1]), 20000.0) << r.out;
}

TEST_F(CliTest, SetOverridesNestedKeysAndListItems) {
  write("base.yaml", drop_scene);
  Result r = cgdem("check base.yaml --set groups.0.count=123 --set materials.beads.youngs_modulus=5e7");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("particles    123"), std::string::npos) << r.out;
  // A stiffer material shortens the contact and so the stable limit printed by check.
  const Result soft = cgdem("check base.yaml --set time.step=auto");
  r = cgdem("check base.yaml --set time.step=auto --set materials.beads.youngs_modulus=5e8");
  std::smatch ms, mh;
  const std::regex step("time step +([0-9.e+-]+) s");
  ASSERT_TRUE(std::regex_search(soft.out, ms, step)) << soft.out;
  ASSERT_TRUE(std::regex_search(r.out, mh, step)) << r.out;
  EXPECT_LT(std::stod(mh[1]), std::stod(ms[1]));
  r = cgdem("check base.yaml --set 'walls.0.motion={velocity: [0,0,0.01]}' --set walls.0.motion.start=0.01");
  EXPECT_EQ(r.code, 0) << r.err;
  r = cgdem("check base.yaml --set groups.3.count=10");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("groups.3"), std::string::npos) << r.err;
}

// A run's checkpoint holds its last step even when the end is not a multiple of --checkpoint-every, so a
// finished run continues to a later end, and a second stage may change what is not particle state.
TEST_F(CliTest, CheckpointHoldsTheLastStepAndStartsASecondStage) {
  write("base.yaml", drop_scene);
  const auto steps_done = [](const std::string& err) {
    std::smatch m;
    return std::regex_search(err, m, std::regex("done: ([0-9]+) steps")) ? std::stol(m[1]) : -1L;
  };
  ASSERT_EQ(cgdem("run base.yaml --threads 1 --out full.h5").code, 0);
  const Result first =
      cgdem("run base.yaml --threads 1 --out first.h5 --set time.end=0.017 --checkpoint-every 0.01");
  ASSERT_EQ(first.code, 0) << first.err;
  EXPECT_EQ(steps_done(first.err), 3400);
  const Result rest = cgdem("run base.yaml --threads 1 --out rest.h5 --restart first.checkpoint.h5");
  ASSERT_EQ(rest.code, 0) << rest.err;
  EXPECT_EQ(steps_done(rest.err), 8000 - 3400); // from 0.017 s, not from the checkpoint at 0.01 s
  const Result softer = cgdem("run base.yaml --threads 1 --out softer.h5 --restart first.checkpoint.h5 "
                              "--set materials.beads.restitution=0.2");
  ASSERT_EQ(softer.code, 0) << softer.err;
  // The periodic sides removed (the sample set free): the pairs across the former seam simply part.
  const Result free =
      cgdem("run base.yaml --threads 1 --out free.h5 --restart first.checkpoint.h5 --set "
            "'domain={lo: [-0.01, -0.01, 0], hi: [0.02, 0.02, 0.03], periodic: [false, false, false]}'");
  ASSERT_EQ(free.code, 0) << free.err;
  EXPECT_EQ(free.err.find("outside the domain"), std::string::npos) << free.err;
  hid_t a = H5Fopen((dir / "full.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t b = H5Fopen((dir / "rest.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t c = H5Fopen((dir / "softer.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const auto full = read_doubles(a, last_frame(a) + "/velocity");
  EXPECT_TRUE(full == read_doubles(b, last_frame(b) + "/velocity"));  // bitwise
  EXPECT_FALSE(full == read_doubles(c, last_frame(c) + "/velocity")); // the second stage's restitution acts
  H5Fclose(a);
  H5Fclose(b);
  H5Fclose(c);
}

TEST_F(CliTest, RestartFromCheckpointEqualsUninterruptedRunBitwise) {
  write("base.yaml", drop_scene);
  ASSERT_EQ(cgdem("run base.yaml --quiet --threads 1 --out full.h5").code, 0);
  // Same run with a checkpoint at 0.02 s, then a continuation from it.
  ASSERT_EQ(cgdem("run base.yaml --quiet --threads 1 --out half.h5 --checkpoint-every 0.02").code, 0);
  ASSERT_TRUE(fs::exists(dir / "half.checkpoint.h5"));
  // The checkpoint holds the last multiple of 0.02 s: the end (0.04 s). Take one from mid-run instead.
  ASSERT_EQ(
      cgdem("run base.yaml --quiet --threads 1 --out mid.h5 --set time.end=0.02 --checkpoint-every 0.02")
          .code,
      0);
  const Result r = cgdem("run base.yaml --quiet --threads 2 --out cont.h5 --restart mid.checkpoint.h5");
  ASSERT_EQ(r.code, 0) << r.err;
  hid_t a = H5Fopen((dir / "full.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t b = H5Fopen((dir / "cont.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  for (const char* field : {"position", "velocity", "angular_velocity"}) {
    const auto x = read_doubles(a, last_frame(a) + "/" + field);
    const auto y = read_doubles(b, last_frame(b) + "/" + field);
    ASSERT_EQ(x.size(), 1500u);
    EXPECT_TRUE(x == y) << field << " differs after restart"; // bitwise
  }
  H5Fclose(a);
  H5Fclose(b);
}

// Analyses that accumulate over outputs (a running peak, a height and an origin measured at the first
// output) continue from the checkpoint: the restarted run ends with the uninterrupted run's values, also
// when it restarts between two outputs (that extra frame is kept out of the peak).
// The drop scene with analyses that accumulate, and its run split at 0.03375 s, between the outputs at
// 0.0325 s (the impact on the floor) and 0.035 s.
const char* accumulating_analyses = R"(analyses:
  - {type: unconfined_strength, name: peak, wall: floor, area: 1.0e-4}
  - {type: wall_stress, name: floor_stress, wall: floor, area: 1.0e-4}
  - {type: planar_flow, name: flow, axis: x}
)";
const char* accumulating_run = "run base.yaml --quiet --threads 1 --set output.every=0.0025";
const char* accumulating_split = "0.03375";

TEST_F(CliTest, RestartContinuesTheAnalysesAccumulations) {
  write("base.yaml", std::string(drop_scene) + accumulating_analyses);
  ASSERT_TRUE(run_whole_and_in_two_parts(accumulating_run, accumulating_split));
  hid_t a = H5Fopen((dir / "full.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t b = H5Fopen((dir / "cont.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  for (const char* v : {"peak", "peak_peak_strain", "floor_stress_strain", "flow", "flow_front"}) {
    const auto x = read_doubles(a, std::string("series/") + v),
               y = read_doubles(b, std::string("series/") + v);
    ASSERT_FALSE(x.empty()) << v;
    ASSERT_FALSE(y.empty()) << v;
    EXPECT_EQ(x.back(), y.back()) << v << " differs after the restart";
  }
  // The peak came before the checkpoint: the continuation alone would not have seen it.
  const auto peak = read_doubles(a, "series/peak"), current = read_doubles(b, "series/peak_stress");
  EXPECT_GT(peak.back(), *std::max_element(current.begin(), current.end()));
  H5Fclose(a);
  H5Fclose(b);
  // A checkpoint of a scene without these analyses cannot continue one with them.
  write("plain.yaml", drop_scene);
  ASSERT_EQ(
      cgdem("run plain.yaml --quiet --threads 1 --out plain.h5 --set time.end=0.01 --checkpoint-every 0.01")
          .code,
      0);
  const Result bad = cgdem(std::string(accumulating_run) + " --out bad.h5 --restart plain.checkpoint.h5");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("lacks the state of analysis"), std::string::npos) << bad.err;
}

// `cgdem analyse` evaluates the scene's analyses again over a run's frames and gives what the run gave:
// from one file, and from the parts of a run continued from a checkpoint between two outputs (the extra
// frame at the restart kept out of the peak, as the run keeps it). With other parameters it gives what
// they give, and a misspelt one is refused like the run refuses it.
TEST_F(CliTest, AnalyseRecomputesTheRunsAnalysesFromItsFrames) {
  write("base.yaml", std::string(drop_scene) + accumulating_analyses);
  ASSERT_TRUE(run_whole_and_in_two_parts(accumulating_run, accumulating_split));
  // "name value" lines, the values printed to the last digit.
  auto outputs = [](const std::string& text) {
    std::map<std::string, double> v;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) { // strtod, not >>: it reads "nan"
      const std::size_t space = line.find(' ');
      if (space != std::string::npos)
        v[line.substr(0, space)] = std::strtod(line.c_str() + space + 1, nullptr);
    }
    return v;
  };
  hid_t file = H5Fopen((dir / "full.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const int frames = frame_count(file);
  const char* names[] = {"peak", "peak_peak_strain", "floor_stress", "floor_stress_strain",
                         "flow", "flow_front"};
  std::map<std::string, double> run;
  for (const char* v : names)
    run[v] = read_doubles(file, std::string("series/") + v).back();
  H5Fclose(file);
  ASSERT_GT(run["peak"], 0);

  const Result whole = cgdem("analyse full.h5 --csv frames.csv");
  ASSERT_EQ(whole.code, 0) << whole.err;
  const Result parts = cgdem("analyse mid.h5 cont.h5");
  ASSERT_EQ(parts.code, 0) << parts.err;
  const auto from_whole = outputs(whole.out), from_parts = outputs(parts.out);
  for (const char* v : names) {
    ASSERT_EQ(from_whole.count(v), 1u) << v << " not printed: " << whole.out;
    EXPECT_EQ(from_whole.at(v), run[v]) << v; // bitwise
    EXPECT_EQ(from_parts.at(v), run[v]) << v << " from the two parts";
  }
  // One row per frame, the outputs as columns.
  std::istringstream csv(slurp(dir / "frames.csv"));
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("time,step,floor_stress,", 0), 0u) << header;
  int rows = 0;
  while (std::getline(csv, line))
    ++rows;
  EXPECT_EQ(rows, frames);

  // The continuation alone never saw the peak of the impact, which came before its checkpoint.
  EXPECT_LT(outputs(cgdem("analyse cont.h5").out).at("peak"), run["peak"]);
  // Another parameter, another value: twice the area, half the stress.
  const auto wider = outputs(cgdem("analyse full.h5 --set analyses.0.area=2.0e-4").out);
  EXPECT_DOUBLE_EQ(wider.at("peak"), 0.5 * run["peak"]);
  const Result typo = cgdem("analyse full.h5 --set analyses.0.aera=2.0e-4");
  EXPECT_EQ(typo.code, 2);
  EXPECT_NE(typo.err.find("analyses.0.aera"), std::string::npos) << typo.err;
  const Result missing = cgdem("analyse nothing.h5");
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("nothing.h5"), std::string::npos) << missing.err;
}

TEST_F(CliTest, SigkillMidRunLeavesEveryCompletedFrameReadable) {
  write("base.yaml", drop_scene);
  for (int attempt = 0; attempt < 3; ++attempt) {
    for (const char* f : {"killed.h5", "killed.xdmf", "killed.h5.shadow"})
      fs::remove(dir / f);
    const pid_t pid = fork();
    if (pid == 0) {
      chdir(dir.c_str());
      freopen("/dev/null", "w", stderr);
      execl(CGDEM_BINARY, CGDEM_BINARY, "run", "base.yaml", "--quiet", "--threads", "1", "--out", "killed.h5",
            "--set", "output.every=0.0005", "--set", "time.end=1.0", static_cast<char*>(nullptr));
      _exit(127);
    }
    // Wait until the XDMF lists a few frames, then kill at a different moment each attempt.
    for (int wait = 0; wait < 600; ++wait) {
      const std::string x = slurp(dir / "killed.xdmf");
      std::size_t grids = 0;
      for (std::size_t at = x.find("<Grid Name=\"frame"); at != std::string::npos;
           at = x.find("<Grid Name=\"frame", at + 1))
        ++grids;
      if (grids >= 3) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(37 * attempt * attempt));
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the run should still have been going";
    // Every frame the file says is complete reads back with the right shapes and finite data.
    hid_t f = H5Fopen((dir / "killed.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    ASSERT_GE(f, 0) << "killed file does not open";
    std::int64_t complete = 0;
    hid_t attr = H5Aopen(f, "frames_complete", H5P_DEFAULT);
    ASSERT_GE(attr, 0);
    H5Aread(attr, H5T_NATIVE_INT64, &complete);
    H5Aclose(attr);
    EXPECT_GE(complete, 3) << "attempt " << attempt;
    for (std::int64_t k = 0; k < complete; ++k) {
      char name[64];
      std::snprintf(name, sizeof name, "/frames/%06lld/position", static_cast<long long>(k));
      const auto x = read_doubles(f, name);
      ASSERT_EQ(x.size(), 1500u) << name;
      for (double v : x)
        ASSERT_TRUE(std::isfinite(v));
    }
    H5Fclose(f);
  }
}

TEST(KokkosSessionTest, PinsThreadsOnlyWhenTheyFillTheCores) {
  // Two single-threaded runs side by side on two cores must not both be bound to the first one.
  EXPECT_STREQ(cgdem::default_proc_bind(1, 2, 1), "false");
  EXPECT_STREQ(cgdem::default_proc_bind(2, 4, 1), "false");
  // A process that has the machine keeps each particle range on one core.
  EXPECT_STREQ(cgdem::default_proc_bind(2, 2, 1), "spread");
  EXPECT_STREQ(cgdem::default_proc_bind(1, 1, 1), "spread");
  EXPECT_STREQ(cgdem::default_proc_bind(0, 2, 1), "spread"); // 0: OpenMP's default, one thread per core
  EXPECT_STREQ(cgdem::default_proc_bind(3, 2, 1), "spread");
  // MPI ranks are placed by mpirun.
  EXPECT_STREQ(cgdem::default_proc_bind(2, 2, 2), "false");
  EXPECT_GE(cgdem::usable_cores(), 1);
}

TEST_F(CliTest, SameTrajectoryBitwiseOnOneAndTwoThreadsAndSerial) {
  // The shared dense bed (10k particles), 1000 steps with the benchmark material.
  std::string scene = R"(domain: {lo: [0, 0, 0], hi: [0.02031, 0.02031, 0.04], periodic: [true, true, false]}
gravity: [0, 0, -9.81]
materials:
  beads: {density: 2500, youngs_modulus: 5.0e6, poisson_ratio: 0.3, restitution: 0.9, friction: 0.3}
contact: {normal: hertz, tangential: mindlin}
groups:
  - name: bed
    material: beads
    placement: {type: file, file: )" CGDEM_SHARED_DIR R"(/data/settled_bed_10k.csv}
walls:
  - {name: floor, type: plane, material: beads, point: [0, 0, 0], normal: [0, 0, 1]}
time: {end: 0.01, step: 1.0e-5}
output: {every: 0.01, file: bed.h5}
stability: {overlap_tolerance: 0.05}
)";
  write("bed.yaml", scene);
  auto final_state = [&](const char* file) {
    hid_t f = H5Fopen((dir / file).c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    std::vector<double> all;
    for (const char* field : {"position", "velocity", "angular_velocity"}) {
      auto v = read_doubles(f, last_frame(f) + "/" + field);
      all.insert(all.end(), v.begin(), v.end());
    }
    H5Fclose(f);
    return all;
  };
  // Shake the bed so that the lists are rebuilt and particles reordered during the 1000 steps; Hertz-Mindlin,
  // then full JKR (its closed-form contact radius runs in the vectorized loop over pairs, which must give
  // each pair the bits it would get alone).
  const std::string shake = " --set 'walls.0.motion={velocity: [0,0,0.05]}'";
  for (const std::string law : {"", " --set contact.normal=jkr --set materials.beads.surface_energy=0.05 "
                                    "--set contact.wall_adhesion=false"}) {
    SCOPED_TRACE(law.empty() ? "hertz" : "jkr");
    ASSERT_EQ(cgdem("run bed.yaml --quiet --threads 1 --out t1.h5" + shake + law).code, 0);
    ASSERT_EQ(cgdem("run bed.yaml --quiet --threads 2 --out t2.h5" + shake + law).code, 0);
    ASSERT_EQ(cgdem("run bed.yaml --quiet --backend serial --out serial.h5" + shake + law).code, 0);
    const auto one = final_state("t1.h5"), two = final_state("t2.h5"), serial = final_state("serial.h5");
    ASSERT_EQ(one.size(), 90000u);
    EXPECT_TRUE(one == two) << "1 vs 2 OpenMP threads differ";
    EXPECT_TRUE(one == serial) << "OpenMP vs Serial differ";

    // The pairs force pass (the GPU's; kernels/contact_forces.hpp): bitwise its own trajectory on every
    // backend and thread count, and the blocks pass's to round-off (the same pairs, summed in another order).
    const std::string pairs = " --set 'neighbour={force_pass: pairs}'";
    ASSERT_EQ(cgdem("run bed.yaml --quiet --threads 1 --out p1.h5" + shake + law + pairs).code, 0);
    ASSERT_EQ(cgdem("run bed.yaml --quiet --threads 2 --out p2.h5" + shake + law + pairs).code, 0);
    ASSERT_EQ(cgdem("run bed.yaml --quiet --backend serial --out pserial.h5" + shake + law + pairs).code, 0);
    const auto p1 = final_state("p1.h5"), p2 = final_state("p2.h5"), pserial = final_state("pserial.h5");
    EXPECT_TRUE(p1 == p2) << "pairs pass: 1 vs 2 OpenMP threads differ";
    EXPECT_TRUE(p1 == pserial) << "pairs pass: OpenMP vs Serial differ";
    ASSERT_EQ(p1.size(), one.size());
    EXPECT_TRUE(p1 != one) << "the two passes sum in different orders: some bit should differ";
    // The last bits of the sums differ from the first step on, and a dense, shaken bed amplifies them over
    // the 1000 steps (contacts that open or close a step apart, rattlers' spins): measured here, positions
    // agree to 1e-13 m (3e-10 of a radius) and spins to 1e-8 of the fastest. The bounds leave room above
    // that and stay far below any physical difference.
    const double bound[3] = {1e-9 * 0.5e-3 / 0.022, 1e-6, 1e-6}; // of each field's largest value
    for (int field = 0; field < 3; ++field) {
      double largest = 0, deviation = 0;
      for (std::size_t k = field * 30000u; k < (field + 1) * 30000u; ++k) {
        largest = std::max(largest, std::abs(one[k]));
        deviation = std::max(deviation, std::abs(p1[k] - one[k]));
      }
      std::printf(
          "[ report ] pairs vs blocks pass, field %d: largest deviation %.3g of a largest value %.3g\n",
          field, deviation, largest);
      EXPECT_LE(deviation, bound[field] * largest)
          << "field " << field << " (position, velocity, angular velocity)";
    }
  }
}

TEST_F(CliTest, OutputFollowsTheHdf5AndXdmfContract) {
  write("base.yaml", drop_scene);
  const Result r = cgdem("run base.yaml --quiet --threads 1");
  ASSERT_EQ(r.code, 0) << r.err;
  hid_t f = H5Fopen((dir / "drop.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  for (const char* a :
       {"cgdem_version", "scene", "backend", "threads", "time_step", "scaling_law", "scale_factor"})
    EXPECT_GT(H5Aexists(f, a), 0) << a;
  const int frames = frame_count(f);
  EXPECT_GE(frames, 5);
  for (const char* ds : {"id", "radius", "mass", "group"})
    EXPECT_EQ(shape(f, "/frames/000001/" + std::string(ds)), std::vector<hsize_t>{500}) << ds;
  for (const char* ds : {"position", "velocity", "angular_velocity"})
    EXPECT_EQ(shape(f, "/frames/000001/" + std::string(ds)), (std::vector<hsize_t>{500, 3})) << ds;
  for (const char* ds : {"time", "step", "kinetic_energy", "rotational_energy", "contacts"})
    EXPECT_EQ(shape(f, "/series/" + std::string(ds)), std::vector<hsize_t>{hsize_t(frames)}) << ds;
  EXPECT_EQ(shape(f, "/series/wall_force/floor"), (std::vector<hsize_t>{hsize_t(frames), 3}));
  // The landed beads push the floor down.
  const auto wf = read_doubles(f, "/series/wall_force/floor");
  EXPECT_LT(wf[3 * (frames - 1) + 2], 0);
  // Every dataset the XDMF names exists with the stated dimensions.
  const int checked = expect_xdmf_matches(f, dir / "drop.xdmf", "drop");
  EXPECT_GE(checked, 2 * frames);
  H5Fclose(f);
}

TEST_F(CliTest, ParticlesLeavingTheDomainAreReportedOnceAndCounted) {
  // The drop scene without its floor: the lowest layer (z = 1.5 mm at 0.3 m/s and g) is below z = 0 by
  // the frame at 0.01 s. The run goes on (exit 0), warns once with the first particle and counts at the end.
  write("drop.yaml", drop_scene);
  const Result r = cgdem("run drop.yaml --quiet --set 'walls=[]' --set time.end=0.02");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: t = 0.01 s:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("outside the domain (first: id"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("domain z in [0, 0.03] m"), std::string::npos) << r.err;
  std::size_t warnings = 0;
  for (std::size_t at = r.err.find("warning:"); at != std::string::npos; at = r.err.find("warning:", at + 1))
    ++warnings;
  EXPECT_EQ(warnings, 1u) << r.err;
  EXPECT_NE(r.err.find("particle(s) outside the domain in the last frame"), std::string::npos) << r.err;
  // With the floor nothing escapes and nothing is said.
  const Result ok = cgdem("run drop.yaml --quiet --set time.end=0.02");
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(ok.err.find("outside the domain"), std::string::npos) << ok.err;
}

// ------------------------------------------------------------------------------------------------
// Reliability (docs/reliability.md): bad output paths, scenes too large for the machine, a full disk and
// truncated or corrupt inputs each end in one clear message and an exit code, never an abort.

std::size_t lines(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

TEST_F(CliTest, OutputPathsAreCheckedBeforeTheRun) {
  write("base.yaml", drop_scene);
  write("plain", "a file, not a directory\n");
  fs::create_directory(dir / "outdir");
  fs::create_directory(dir / "cp.checkpoint.h5");
  fs::create_directory(dir / "x.xdmf");
  struct Case {
    std::string args, names;
  };
  const std::vector<Case> cases = {
      {"run base.yaml --out outdir", "outdir"},             // an existing directory
      {"run base.yaml --out plain/r.h5", "plain"},          // a file as the parent
      {"run base.yaml --out /proc/cgdem_test.h5", "/proc"}, // cannot be written, even by root
      {"run base.yaml --out cp.h5 --checkpoint-every 0.01", "cp.checkpoint.h5"}, // checkpoint name taken
      {"run base.yaml --out x.h5", "x.xdmf"},                                    // XDMF name taken
      {"sweep base.yaml --laws bond --k 2 --out plain", "plain"},
      {"stability base.yaml --dts 1e-6,2e-6 --out plain", "plain"},
      {"stability base.yaml --dts 1e-6,2e-6 --out /proc/cgdem_stab", "/proc"},
  };
  for (const Case& c : cases) {
    const Result r = cgdem(c.args);
    EXPECT_EQ(r.code, 2) << c.args << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1u) << c.args << ": " << r.err;
    EXPECT_NE(r.err.find(c.names), std::string::npos) << c.args << ": " << r.err;
  }
  EXPECT_TRUE(fs::is_empty(dir / "outdir"));
  EXPECT_FALSE(fs::exists(dir / "cp.h5"));
  EXPECT_FALSE(fs::exists(dir / "x.h5"));
}

// A sweep checks every run as `cgdem check` would before the first starts: at k = 4 the 10 mm periodic axes
// are shorter than 3 neighbour cells of 4 mm particles, so nothing runs and nothing is written.
std::string drop_scene_free_spacing() { // the lattice spaced by the particles' size at every k
  std::string s = drop_scene;
  s.erase(s.find("      spacing: 0.00105\n"), std::string("      spacing: 0.00105\n").size());
  return s;
}

TEST_F(CliTest, SweepWhoseCoarseRunWouldFailStopsBeforeAnyRun) {
  write("base.yaml", drop_scene_free_spacing());
  const Result r = cgdem("sweep base.yaml --laws bond --k 2,4 --no-plots --out sw");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("run bond_k4 (law bond, k = 4) would fail, nothing was run"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("periodic axis x"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "sw"));
}

// Each run's particle count and mass go to sweep.csv with its mass against the reference's, and a run whose
// mass differs by more than 1 % is named (300 originals: 38 coarse particles of 8 originals each, +1.3 %).
TEST_F(CliTest, SweepRecordsEachRunsMassAndNamesAMismatch) {
  write("base.yaml", drop_scene_free_spacing());
  const Result r =
      cgdem("sweep base.yaml --laws bond --k 2 --no-plots --quiet --out sw --set groups.0.count=300 "
            "--set time.end=0.002 --set output.every=0.001");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("bond_k2: its 38 particles weigh +1.3 % against the reference's 300"),
            std::string::npos)
      << r.err;
  std::ifstream in(dir / "sw" / "sweep.csv");
  std::string header, line;
  std::getline(in, header);
  const auto column = [&](const std::string& row, const std::string& name) {
    std::vector<std::string> h, v;
    std::stringstream hs(header), vs(row);
    for (std::string c; std::getline(hs, c, ',');)
      h.push_back(c);
    for (std::string c; std::getline(vs, c, ',');)
      v.push_back(c);
    for (std::size_t c = 0; c < h.size() && c < v.size(); ++c)
      if (h[c] == name) return v[c];
    return std::string("missing");
  };
  const double bead = 2500 * 4.0 / 3.0 * M_PI * 0.0005 * 0.0005 * 0.0005;
  int rows = 0;
  while (std::getline(in, line)) {
    ++rows;
    const bool reference = line.rfind("reference,", 0) == 0;
    EXPECT_NEAR(std::stod(column(line, "mass_kg")), 300 * bead * (reference ? 1 : 38.0 * 8 / 300),
                1e-9 * bead)
        << line;
    EXPECT_NEAR(std::stod(column(line, "mass_ratio")), reference ? 1 : 38.0 * 8 / 300, 1e-12) << line;
  }
  EXPECT_EQ(rows, 2);
}

TEST_F(CliTest, SceneTooLargeForTheMachineIsRefusedWithBothFigures) {
  write("base.yaml", drop_scene);
  for (const char* command : {"check", "run"}) {
    const Result r = cgdem(std::string(command) + " base.yaml --set groups.0.count=1000000000000" +
                           (command == std::string("run") ? " --out big.h5" : ""));
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("groups.0.count"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("need at least"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("this machine has"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("bad_alloc"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "big.h5"));
}

// A full disk, simulated by a file-size limit (RLIMIT_FSIZE with SIGXFSZ ignored, so writes fail with EFBIG):
// exit code 4, the result file holds every frame committed before, and the checkpoint asked for is written.
TEST_F(CliTest, FullDiskStopsTheRunKeepingEveryFrameAndACheckpoint) {
  write("base.yaml", drop_scene);
  const std::string args =
      "run base.yaml --quiet --threads 1 --out full.h5 --set time.end=0.01 --set output.every=0.0005 "
      "--checkpoint-every 0.005";
  // dash and bash count ulimit -f in 512 or 1024-byte blocks: the checkpoint (~220 kB) and some of the ~20
  // frames (~70 kB each) fit either way.
  const Result r = cgdem(args, "trap '' XFSZ; ulimit -f 1200;");
  ASSERT_EQ(r.code, 4) << r.err;
  EXPECT_NE(r.err.find("output write failed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("full.h5"), std::string::npos) << r.err;
  hid_t f = H5Fopen((dir / "full.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0) << "the result file does not open after the failure";
  std::int64_t complete = 0;
  hid_t attr = H5Aopen(f, "frames_complete", H5P_DEFAULT);
  ASSERT_GE(attr, 0);
  H5Aread(attr, H5T_NATIVE_INT64, &complete);
  H5Aclose(attr);
  EXPECT_GE(complete, 1);
  EXPECT_LT(complete, 21) << "the limit should have stopped the run early";
  EXPECT_EQ(frame_count(f), complete);
  for (std::int64_t k = 0; k < complete; ++k) {
    char name[64];
    std::snprintf(name, sizeof name, "/frames/%06lld/position", static_cast<long long>(k));
    EXPECT_EQ(read_doubles(f, name).size(), 1500u) << name;
  }
  H5Fclose(f);
  EXPECT_NE(r.err.find("keeps " + std::to_string(complete) + " complete frames"), std::string::npos) << r.err;
  // The checkpoint written at the failure continues the run.
  ASSERT_TRUE(fs::exists(dir / "full.checkpoint.h5")) << r.err;
  const Result cont = cgdem("run base.yaml --quiet --threads 1 --out cont.h5 --set time.end=0.01 "
                            "--restart full.checkpoint.h5");
  EXPECT_EQ(cont.code, 0) << cont.err;
}

// Truncated and corrupt checkpoints, CSV and HDF5 particle files: exit 2 with one line naming the file,
// and the output of an earlier run (same --out) is left exactly as it was.
TEST_F(CliTest, CorruptInputsGiveExitTwoAndLeaveEarlierOutputIntact) {
  write("base.yaml", drop_scene);
  const std::string quick = " --quiet --threads 1 --set time.end=0.001 --set output.every=0.0005";
  ASSERT_EQ(cgdem("run base.yaml --out good.h5 --checkpoint-every 0.0005" + quick).code, 0);
  const std::string good_h5 = slurp(dir / "good.h5"), good_xdmf = slurp(dir / "good.xdmf");
  const std::string checkpoint = slurp(dir / "good.checkpoint.h5");
  ASSERT_GT(checkpoint.size(), 1000u);
  auto corrupt = [](std::string bytes, std::size_t from, std::size_t every) {
    for (std::size_t i = from; i < bytes.size(); i += every)
      bytes[i] = static_cast<char>(bytes[i] ^ 0x5a);
    return bytes;
  };
  auto put = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(dir / name, std::ios::binary) << bytes;
  };
  put("cp_half.h5", checkpoint.substr(0, checkpoint.size() / 2));
  put("cp_head.h5", checkpoint.substr(0, 100));
  put("cp_empty.h5", "");
  put("cp_flipped.h5", corrupt(checkpoint, 2048, 61));
  put("cp_super.h5", corrupt(checkpoint, 8, 13).substr(0, 4096) + checkpoint.substr(4096));
  ASSERT_EQ(
      cgdem("run base.yaml --out other.h5 --set groups.0.count=50 --checkpoint-every 0.0005" + quick).code,
      0); // a checkpoint of another scene (50 particles, not 500)
  put("r_half.h5", good_h5.substr(0, good_h5.size() / 2));
  put("r_flipped.h5", corrupt(good_h5, 2048, 61));
  write("truncated.csv", "id,x,y,z,radius\n1,0.005,0.005,0.005,0.0005\n2,0.005,0.0");
  write("garbage.csv", std::string("\x01\x02\xff,,\n\0\0x,y\n", 12));
  write("header_only.csv", "id,x,y,z,radius\n");
  write("nan.csv", "x,y,z,radius\nnan,0.005,0.005,0.0005\n");
  write("negative.csv", "x,y,z,radius\n0.005,0.005,0.005,-1\n");
  write("huge_id.csv", "id,x,y,z,radius\n1e300,0.005,0.005,0.005,0.0005\n");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--restart cp_half.h5", "cp_half.h5"},
      {"--restart cp_head.h5", "cp_head.h5"},
      {"--restart cp_empty.h5", "cp_empty.h5"},
      {"--restart cp_flipped.h5", "cp_flipped.h5"},
      {"--restart cp_super.h5", "cp_super.h5"},
      {"--restart other.checkpoint.h5", "other.checkpoint.h5"},
      {"--restart no_such.checkpoint.h5", "no_such.checkpoint.h5"},
      {"--restart good.h5", "good.h5"}, // a result file, not a checkpoint
  };
  std::vector<std::pair<std::string, std::string>> all = cases;
  for (const char* file : {"r_half.h5", "r_flipped.h5", "truncated.csv", "garbage.csv", "header_only.csv",
                           "nan.csv", "negative.csv", "huge_id.csv"})
    all.push_back({std::string("--set 'groups.0={name: g, material: beads, placement: {type: file, file: ") +
                       file + "}}'",
                   file});
  for (const auto& c : all) {
    const Result r = cgdem("run base.yaml --out good.h5 " + c.first + quick);
    EXPECT_EQ(r.code, 2) << c.first << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1u) << c.first << ": " << r.err;
    EXPECT_NE(r.err.find(c.second), std::string::npos) << c.first << ": " << r.err;
    EXPECT_TRUE(slurp(dir / "good.h5") == good_h5) << c.first << " changed the earlier result";
    EXPECT_TRUE(slurp(dir / "good.xdmf") == good_xdmf) << c.first << " changed the earlier XDMF";
  }
}

// A piston that loads the settled beads at constant speed until they push back with until_force, then
// holds its position (Thakur's loading to a target stress): the segment ends at the first check at or
// above the force, never earlier; the piston stays where it stopped; restarts from checkpoints before and
// after that moment end bitwise on the uninterrupted run (the ended segment travels in the checkpoint).
TEST_F(CliTest, SegmentEndsWhenTheParticlesPushBackWithUntilForce) {
  std::string scene = std::string(drop_scene) + R"(analyses:
  - {type: wall_stress, name: load, wall: piston, area: 1.0e-4, initial_height: 0.01}
)";
  const std::string floor = "    normal: [0, 0, 1]\n";
  scene.insert(scene.find(floor) + floor.size(), R"(  - name: piston
    type: plane
    material: beads
    point: [0, 0, 0.010]
    normal: [0, 0, -1]
    motion: {velocity: [0, 0, 0], then: [{velocity: [0, 0, -0.2], start: 0.03, stop: 0.06, until_force: 0.05}]}
)");
  write("base.yaml", scene);
  // `cgdem check` says what the segment does.
  const Result check = cgdem("check base.yaml");
  ASSERT_EQ(check.code, 0) << check.err;
  EXPECT_NE(
      check.out.find("wall piston       motion.then.0 ends at 0.05 N against its velocity (until_force), "
                     "else at 0.06 s"),
      std::string::npos)
      << check.out;
  const std::string common = "run base.yaml --threads 1 --set time.end=0.06 --set output.every=0.0005 ";
  const Result full = cgdem(common + "--out full.h5");
  ASSERT_EQ(full.code, 0) << full.err;
  std::smatch m;
  ASSERT_TRUE(
      std::regex_search(full.err, m, std::regex("t = ([0-9.e+-]+) s: the particles push wall 'piston'")))
      << full.err;
  const double ended = std::stod(m[1]);
  EXPECT_GT(ended, 0.03);
  EXPECT_LT(ended, 0.06);
  hid_t f = H5Fopen((dir / "full.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const auto time = read_doubles(f, "series/time"), load = read_doubles(f, "series/load"),
             strain = read_doubles(f, "series/load_strain");
  H5Fclose(f);
  ASSERT_EQ(time.size(), load.size());
  ASSERT_EQ(time.size(), strain.size());
  std::size_t before = 0, after = 0;
  double held = std::nan("");
  for (std::size_t r = 0; r < time.size(); ++r) {
    if (time[r] < 0.03) continue;
    // Every output from 0.03 s on is a check step: below the force until the end, the wall still.
    if (time[r] < ended - 1e-9) {
      EXPECT_LT(load[r] * 1.0e-4, 0.05) << "t = " << time[r];
      ++before;
    } else {
      if (after == 0) held = strain[r];
      EXPECT_EQ(strain[r], held) << "the piston moved at t = " << time[r];
      ++after;
    }
  }
  EXPECT_GT(before, 3u);
  EXPECT_GT(after, 3u);
  EXPECT_GT(held, 0);
  // Restarts from before and after the end of the segment.
  ASSERT_GT(ended, 0.035);
  ASSERT_LT(ended, 0.055);
  for (const char* at : {"0.035", "0.055"}) {
    const std::string stem = std::string("mid") + at;
    ASSERT_EQ(cgdem(common + "--out " + stem + ".h5 --set time.end=" + at + " --checkpoint-every " + at).code,
              0);
    const Result r = cgdem(common + "--out cont" + at + ".h5 --restart " + stem + ".checkpoint.h5");
    ASSERT_EQ(r.code, 0) << r.err;
    hid_t a = H5Fopen((dir / "full.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    hid_t b = H5Fopen((dir / ("cont" + std::string(at) + ".h5")).c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    EXPECT_TRUE(read_doubles(a, last_frame(a) + "/velocity") == read_doubles(b, last_frame(b) + "/velocity"))
        << "restart at " << at;
    EXPECT_EQ(read_doubles(b, "series/load_strain").back(), held) << "restart at " << at;
    H5Fclose(a);
    H5Fclose(b);
  }
}
