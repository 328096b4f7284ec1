// `cgdem sweep` end to end on the tiny scene (sweeps/tiny_pile.yaml): CSV columns, plots, resume after
// pre-created records and after a kill, and speed-up / error recomputed from the per-run records.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <thread>
#include "drivers/analyses.hpp"
#include "drivers/cli.hpp"
#include "drivers/scene_parser.hpp"
#include "drivers/sweep_command.hpp"
#include "drivers/sweep_statistics.hpp"

using namespace cgdem;
namespace fs = std::filesystem;

namespace {

const std::string kScene = CGDEM_SOURCE_DIR "/sweeps/tiny_pile.yaml";

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Csv {
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  double num(std::size_t r, const std::string& c) const { return std::stod(rows.at(r).at(c)); }
  std::size_t find(const std::string& run) const {
    for (std::size_t r = 0; r < rows.size(); ++r)
      if (rows[r].at("run") == run) return r;
    return rows.size();
  }
};

Csv read_csv(const fs::path& p) {
  Csv c;
  std::ifstream in(p);
  std::string line;
  auto cells = [](const std::string& l) {
    std::vector<std::string> v;
    std::stringstream ss(l);
    std::string x;
    while (std::getline(ss, x, ','))
      v.push_back(x);
    if (!l.empty() && l.back() == ',') v.push_back("");
    return v;
  };
  std::getline(in, line);
  c.header = cells(line);
  while (std::getline(in, line)) {
    const auto v = cells(line);
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < c.header.size(); ++k)
      row[c.header[k]] = k < v.size() ? v[k] : "";
    c.rows.push_back(row);
  }
  return c;
}

class SweepTest : public ::testing::Test {
protected:
  fs::path dir;
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("cgdem_sweep_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
           "_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  // Short runs: 0.05 s of simulated time.
  std::string args(const std::string& extra) const {
    return "sweep '" + kScene + "' --laws chen_elliott --k 1,2,3 --set time.end=0.05 --out '" +
           (dir / "s").string() + "' --threads 2 " + extra;
  }
  int cgdem(const std::string& a) {
    const std::string cmd = "'" CGDEM_BINARY "' " + a + " > '" + (dir / "out.txt").string() + "' 2>&1";
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
};

} // namespace

TEST(SweepOptions, ParseAndReject) {
  const SweepOptions o =
      parse_sweep_options({"s.yaml", "--laws", "a,b", "--k", "3,1,2,2", "--policy=serial"});
  EXPECT_EQ(o.laws, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(o.factors, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(o.policy, "serial");
  EXPECT_THROW(parse_sweep_options({"s.yaml", "--laws", "a", "--k", "0.5"}), CliError);
  EXPECT_THROW(parse_sweep_options({"s.yaml", "--k", "2"}), CliError);
  EXPECT_THROW(parse_sweep_options({"s.yaml", "--laws", "a", "--k", "2", "--policy", "fast"}), CliError);
  // Seeds: the reference takes --seeds unless given its own; a repeated or negative seed is refused.
  const SweepOptions seeded = parse_sweep_options(
      {"s.yaml", "--laws", "a", "--k", "2", "--seeds", "3,1,2", "--checkpoint-every", "0.5"});
  EXPECT_EQ(seeded.seeds, (std::vector<long>{3, 1, 2}));
  EXPECT_EQ(seeded.reference_seeds, seeded.seeds);
  EXPECT_EQ(seeded.checkpoint_every, 0.5);
  EXPECT_EQ(
      parse_sweep_options({"s.yaml", "--laws", "a", "--k", "2", "--seeds", "1,2,3", "--reference-seeds", "7"})
          .reference_seeds,
      (std::vector<long>{7}));
  EXPECT_TRUE(parse_sweep_options({"s.yaml", "--laws", "a", "--k", "2"}).seeds.empty());
  for (const char* bad : {"1,1", "-1", "x"})
    EXPECT_THROW(parse_sweep_options({"s.yaml", "--laws", "a", "--k", "2", "--seeds", bad}), CliError) << bad;
  EXPECT_THROW(parse_sweep_options({"s.yaml", "--laws", "a", "--k", "2", "--reference-seeds", "1"}),
               CliError);
  EXPECT_THROW(parse_sweep_options({"s.yaml", "--laws", "a", "--k", "2", "--checkpoint-every", "0"}),
               CliError);
  // --coarse-set: one key of the coarse_grain map with its value.
  EXPECT_EQ(
      parse_sweep_options({"s.yaml", "--laws", "a", "--k", "2", "--coarse-set", "surface_energy_power=1"})
          .coarse_sets,
      (std::vector<std::string>{"surface_energy_power=1"}));
  for (const char* bad : {"surface_energy_power", "=1", "x=", "groups.0.coarse_grain.x=1"})
    EXPECT_THROW(parse_sweep_options({"s.yaml", "--laws", "a", "--k", "2", "--coarse-set", bad}), CliError)
        << bad;
}

// Mean and sample standard deviation over seeds, the error of the case's mean against the reference's,
// the scatter sqrt(sd^2 + sd_ref^2) and the verdict, on numbers worked by hand.
TEST(SweepOptions, SeedStatisticsFromRecords) {
  auto record = [](const std::string& law, double k, double angle, double wall, int exit_code = 0) {
    RunRecord r;
    r.run = law;
    r.law = law;
    r.k = k;
    r.wall_time = wall;
    r.cpu_time = wall;
    r.exit_code = exit_code;
    r.values = {{"angle", angle}, {"height", 10}};
    return r;
  };
  // Reference 40, 42: mean 41, sd sqrt(2). Law a: 38, 40, 42: mean 40, sd 2. Law b: 30, 31, 32 (sd 1)
  // and a failed run left out.
  const std::vector<RunRecord> runs{
      record("none", 1, 40, 100), record("none", 1, 42, 60), record("a", 2, 38, 10),
      record("a", 2, 40, 10),     record("a", 2, 42, 20),    record("b", 2, 30, 8),
      record("b", 2, 31, 8),      record("b", 2, 32, 8),     record("b", 2, 0, 1, 3)};
  const auto cases = summarize_cases(runs, {"angle", "height"});
  ASSERT_EQ(cases.size(), 3u);
  EXPECT_EQ(cases[0].law, "none");
  EXPECT_EQ(cases[0].seeds, 2);
  EXPECT_DOUBLE_EQ(cases[0].values.at("angle").mean, 41);
  EXPECT_NEAR(cases[0].values.at("angle").sd, std::sqrt(2.0), 1e-14);
  EXPECT_TRUE(std::isnan(cases[0].within.at("angle"))); // no verdict on the reference itself
  const CaseSummary& a = cases[1];
  EXPECT_EQ(a.law, "a");
  EXPECT_EQ(a.seeds, 3);
  EXPECT_DOUBLE_EQ(a.speedup, 80.0 / (40.0 / 3));
  EXPECT_DOUBLE_EQ(a.values.at("angle").mean, 40);
  EXPECT_NEAR(a.values.at("angle").sd, 2, 1e-14);
  EXPECT_NEAR(a.error.at("angle"), -1.0 / 41, 1e-15);
  EXPECT_NEAR(a.scatter.at("angle"), std::sqrt(4.0 + 2.0) / 41, 1e-15);
  EXPECT_EQ(a.within.at("angle"), 1);
  const CaseSummary& b = cases[2];
  EXPECT_EQ(b.seeds, 3); // the failed run is not a seed
  EXPECT_NEAR(b.error.at("angle"), -10.0 / 41, 1e-15);
  EXPECT_NEAR(b.scatter.at("angle"), std::sqrt(1.0 + 2.0) / 41, 1e-15);
  EXPECT_EQ(b.within.at("angle"), 0);
  // Equal values without spread: zero error within zero scatter; one seed on both sides: no verdict.
  EXPECT_EQ(b.scatter.at("height"), 0);
  EXPECT_EQ(b.within.at("height"), 1);
  EXPECT_TRUE(std::isnan(
      summarize_cases({record("none", 1, 1, 1), record("a", 2, 1, 1)}, {"angle"})[1].within.at("angle")));
  // The mean record the runs are compared with.
  const RunRecord m = mean_record({runs[0], runs[1]}, "reference");
  EXPECT_DOUBLE_EQ(m.values.at("angle"), 41);
  EXPECT_DOUBLE_EQ(m.wall_time, 80);
  EXPECT_EQ(m.exit_code, 0);
  EXPECT_EQ(mean_record({runs[6], runs[8]}, "b").exit_code, 3);
}

TEST(SweepOptions, CompareRunsFromRecords) {
  RunRecord ref, run;
  ref.run = "reference";
  ref.wall_time = 8;
  ref.values = {{"angle", 30}, {"zero", 0}};
  ref.samples["v"] = {0, 1, 2, 3};
  run.run = "x_k2";
  run.wall_time = 2;
  run.values = {{"angle", 27}, {"zero", 0.5}};
  run.samples["v"] = {0.5, 1.5, 2.5, 3.5};
  const auto rows = compare_runs({ref, run}, ref);
  EXPECT_DOUBLE_EQ(rows[0].speedup, 1);
  EXPECT_DOUBLE_EQ(rows[1].speedup, 4);
  EXPECT_NEAR(rows[1].error.at("angle"), 0.1, 1e-15);
  EXPECT_NEAR(rows[1].error.at("zero"), 0.5, 1e-15); // absolute when the reference is 0
  EXPECT_NEAR(rows[1].w1.at("v"), 0.5, 1e-12);
  EXPECT_NEAR(rows[1].ks.at("v"), 0.25, 1e-12);
  // Records round-trip exactly.
  const fs::path p = fs::temp_directory_path() / ("cgdem_record_" + std::to_string(getpid()) + ".txt");
  run.law = "x";
  run.status = "ok";
  run.values["third"] = 1.0 / 3;
  write_record(p.string(), run);
  const RunRecord back = read_record(p.string());
  fs::remove(p);
  EXPECT_EQ(back.run, run.run);
  EXPECT_EQ(back.status, "ok");
  EXPECT_EQ(back.values, run.values);
  EXPECT_EQ(back.samples, run.samples);
  EXPECT_EQ(back.wall_time, run.wall_time);
  // An undefined figure is recorded as nan and read back as nan, not as 0.
  run.values["undefined"] = std::nan("");
  run.samples["v"].push_back(std::nan(""));
  write_record(p.string(), run);
  const RunRecord nan_back = read_record(p.string());
  fs::remove(p);
  EXPECT_TRUE(std::isnan(nan_back.values.at("undefined")));
  EXPECT_EQ(nan_back.values.at("angle"), 27);
  ASSERT_EQ(nan_back.samples.at("v").size(), 5u);
  EXPECT_TRUE(std::isnan(nan_back.samples.at("v").back()));
}

// The error against the reference scaled to the run's mass, ref (m / m_ref)^p: a run 9 % heavier than the
// reference, with an angle (p = 0), a heap height (p = 1/3) and a wall force (p = 1).
TEST(SweepOptions, MassMatchedErrorFromRecords) {
  RunRecord ref, run;
  ref.run = "reference";
  ref.mass = 2.0;
  ref.values = {{"angle", 30}, {"height", 0.01}, {"force", 2.0}, {"unscaled", 5}};
  run.run = "x_k2";
  run.mass = 2.18; // mass ratio 1.09
  run.values = {{"angle", 31}, {"height", 0.0105}, {"force", 2.2}, {"unscaled", 6}};
  SweepAnalyses a;
  a.main = {"angle", "height", "force"};
  a.mass_exponent = {{"angle", 0}, {"height", 1.0 / 3}, {"force", 1}};
  const auto rows = compare_runs({ref, run}, ref, a);
  ASSERT_TRUE(rows[1].ok);
  const auto& mm = rows[1].mass_matched;
  EXPECT_NEAR(mm.at("angle"), 31.0 / 30 - 1, 1e-15); // p = 0: the plain error
  EXPECT_NEAR(mm.at("angle"), rows[1].error.at("angle"), 1e-15);
  EXPECT_NEAR(mm.at("height"), 0.0105 / (0.01 * std::cbrt(1.09)) - 1, 1e-14);
  EXPECT_NEAR(mm.at("height"), 0.02027, 1e-5);        // against 0.05 unmatched
  EXPECT_NEAR(mm.at("force"), 2.2 / 2.18 - 1, 1e-14); // 0.0092 against 0.1 unmatched
  EXPECT_NEAR(rows[1].error.at("force"), 0.1, 1e-14);
  EXPECT_EQ(mm.count("unscaled"), 0u); // no exponent declared: no mass-matched error
  // Below the reference value: |x / x_ref' - 1|, the same form as the plain error.
  EXPECT_NEAR(mass_matched_error(2.0, 2.0, 2.18, 2.0, 1), 1 - 2.0 / 2.18, 1e-15);
  // Equal masses: every mass-matched error is the plain one; an unrecorded mass gives none.
  run.mass = ref.mass;
  const SweepRow equal = compare_runs({run}, ref, a)[0];
  EXPECT_EQ(equal.mass_matched.size(), 3u);
  for (const auto& kv : equal.mass_matched)
    EXPECT_DOUBLE_EQ(kv.second, equal.error.at(kv.first)) << kv.first;
  run.mass = 0;
  EXPECT_TRUE(compare_runs({run}, ref, a)[0].mass_matched.empty());
}

// Each analysis declares how its outputs scale with the sample's mass; mass_exponent overrides the main one.
TEST(SweepOptions, AnalysesDeclareMassExponents) {
  const Scene s = parse_scene_text(R"(domain: {lo: [-1, -1, 0], hi: [1, 1, 1]}
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.001}, placement: {type: lattice}}]
walls: [{name: floor, type: plane, material: m, point: [0, 0, 0], normal: [0, 0, 1]}]
time: {end: 1}
analyses:
  - {type: angle_of_repose, name: pile}
  - {type: wall_stress, name: floor_stress, wall: floor, area: 1, initial_height: 1}
  - {type: wall_stress, name: piston, wall: floor, area: 1, initial_height: 1, mass_exponent: 0}
  - {type: unconfined_strength, name: ucs, wall: floor, area: 1, initial_height: 1}
  - {type: planar_flow, name: flow}
  - {type: profile, name: bed}
)",
                                   "<test>");
  const auto p = mass_exponents(make_analyses(s));
  EXPECT_EQ(p.at("pile"), 0);
  EXPECT_DOUBLE_EQ(p.at("pile_height"), 1.0 / 3);
  EXPECT_DOUBLE_EQ(p.at("pile_foot_radius"), 1.0 / 3);
  EXPECT_EQ(p.at("floor_stress"), 1);
  EXPECT_EQ(p.at("piston"), 0);
  EXPECT_EQ(p.at("ucs"), 0);
  EXPECT_EQ(p.at("flow"), 0.5);
  EXPECT_EQ(p.at("flow_front"), 0);
  EXPECT_EQ(p.at("bed_coordination"), 0);
  const Scene bad = parse_scene_text(R"(domain: {lo: [0, 0, 0], hi: [1, 1, 1]}
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.001}, placement: {type: lattice}}]
time: {end: 1}
analyses: [{type: profile, mass_exponent: third}]
)",
                                     "<test>");
  EXPECT_THROW(make_analyses(bad), SceneError);
  // A misspelt mass_exponent is named with the known parameters, mass_exponent among them.
  const Scene typo = parse_scene_text(R"(domain: {lo: [0, 0, 0], hi: [1, 1, 1]}
materials: {m: {density: 1000, youngs_modulus: 1e6}}
groups: [{material: m, count: 1, size: {radius: 0.001}, placement: {type: lattice}}]
time: {end: 1}
analyses: [{type: profile, mass_exponnet: 1}]
)",
                                      "<test>");
  try {
    make_analyses(typo);
    ADD_FAILURE() << "accepted mass_exponnet";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("known parameters: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mass_exponent"), std::string::npos) << e.what();
  }
}

TEST_F(SweepTest, CsvPlotsAndFiguresFromRecords) {
  ASSERT_EQ(cgdem(args("")), 0) << slurp(dir / "out.txt");
  const fs::path s = dir / "s";
  for (const char* f : {"sweep.csv", "sweep.h5", "speedup.png", "error.png"}) {
    ASSERT_TRUE(fs::exists(s / f)) << f << "\n" << slurp(dir / "out.txt");
    EXPECT_GT(fs::file_size(s / f), 100u) << f;
  }
  const Csv csv = read_csv(s / "sweep.csv");
  for (const char* c : {"run", "law", "k", "status", "particles", "steps", "wall_time_s",
                        "particle_steps_per_s", "speedup", "pile", "err_pile", "pile_height", "floor_stress",
                        "err_floor_stress", "bed", "bed_coordination", "speed", "w1_speed", "ks_speed"})
    EXPECT_NE(std::find(csv.header.begin(), csv.header.end(), c), csv.header.end()) << "column " << c;
  ASSERT_EQ(csv.rows.size(), 3u);
  const std::size_t r1 = csv.find("reference"), r2 = csv.find("chen_elliott_k2"),
                    r3 = csv.find("chen_elliott_k3");
  ASSERT_LT(std::max({r1, r2, r3}), 3u);
  EXPECT_EQ(csv.num(r1, "particles"), 300);
  EXPECT_EQ(csv.num(r2, "particles"), 38); // 300 / 2^3
  EXPECT_EQ(csv.num(r3, "particles"), 11);
  EXPECT_DOUBLE_EQ(csv.num(r1, "speedup"), 1);
  // Recompute from the records.
  const RunRecord ref = read_record((s / "records" / "reference.txt").string());
  for (const char* run : {"chen_elliott_k2", "chen_elliott_k3"}) {
    const RunRecord r = read_record((s / "records" / (std::string(run) + ".txt")).string());
    const std::size_t row = csv.find(run);
    EXPECT_EQ(r.status, "ok");
    EXPECT_NEAR(csv.num(row, "speedup"), ref.wall_time / r.wall_time, 1e-12 * ref.wall_time / r.wall_time);
    EXPECT_NEAR(csv.num(row, "wall_time_s"), r.wall_time, 1e-12 * r.wall_time);
    // CPU seconds of the child process: recorded, positive, and their ratio is speedup_cpu.
    EXPECT_GT(r.cpu_time, 0);
    EXPECT_GT(ref.cpu_time, r.cpu_time);
    EXPECT_NEAR(csv.num(row, "speedup_cpu"), ref.cpu_time / r.cpu_time, 1e-9 * ref.cpu_time / r.cpu_time);
    EXPECT_EQ(csv.num(row, "steps"), r.steps);
    EXPECT_NEAR(csv.num(row, "particle_steps_per_s"), double(r.steps) * r.particles / r.wall_time,
                1e-9 * csv.num(row, "particle_steps_per_s"));
    for (const char* m : {"pile", "floor_stress", "bed"}) {
      const double e = std::abs(r.values.at(m) - ref.values.at(m)) / std::abs(ref.values.at(m));
      EXPECT_NEAR(csv.num(row, std::string("err_") + m), e, 1e-12 * (1 + e)) << run << " " << m;
    }
    EXPECT_NEAR(csv.num(row, "ks_speed"), ks_distance(r.samples.at("speed"), ref.samples.at("speed")), 1e-12);
    EXPECT_NEAR(csv.num(row, "w1_speed"), wasserstein1(r.samples.at("speed"), ref.samples.at("speed")),
                1e-12);
    EXPECT_EQ(r.samples.at("speed").size(), static_cast<std::size_t>(r.particles));
  }
  // The floor carries the weight: the same powder mass at every k (within the settling left after 0.05 s).
  EXPECT_GT(ref.values.at("floor_stress"), 0);
}

// --coarse-set reaches the coarse-grained runs and not the reference: a value the parser refuses stops the
// sweep at the coarse run's check, and a valid one runs (under law none the reference would refuse it).
TEST_F(SweepTest, CoarseSetReachesTheCoarseRunsOnly) {
  ASSERT_EQ(cgdem(args("--no-plots --quiet --coarse-set surface_energy_power=9")), 2)
      << slurp(dir / "out.txt");
  const std::string refused = slurp(dir / "out.txt");
  EXPECT_NE(refused.find("surface_energy_power 9 is outside 0-3"), std::string::npos) << refused;
  EXPECT_FALSE(fs::exists(dir / "s" / "records" / "reference.txt"));
  ASSERT_EQ(cgdem("sweep '" + kScene + "' --laws chen_elliott --k 2 --set time.end=0.01 --out '" +
                  (dir / "s").string() +
                  "' --threads 2 --no-plots --quiet --coarse-set surface_energy_power=1"),
            0)
      << slurp(dir / "out.txt");
  EXPECT_EQ(read_csv(dir / "s" / "sweep.csv").rows.size(), 2u);
}

TEST_F(SweepTest, PreCreatedRecordIsSkippedAndUsed) {
  RunRecord fake;
  fake.run = "chen_elliott_k2";
  fake.law = "chen_elliott";
  fake.k = 2;
  fake.status = "ok";
  fake.particles = 38;
  fake.steps = 100;
  fake.wall_time = 1000;
  fake.values = {{"pile", 45}, {"floor_stress", 1}, {"bed", 0.5}};
  fake.samples["speed"] = {0, 1};
  const fs::path rec = dir / "s" / "records" / "chen_elliott_k2.txt";
  write_record(rec.string(), fake);
  const std::string before = slurp(rec);
  ASSERT_EQ(cgdem(args("--no-plots")), 0) << slurp(dir / "out.txt");
  EXPECT_NE(slurp(dir / "out.txt").find("skip chen_elliott_k2"), std::string::npos) << slurp(dir / "out.txt");
  EXPECT_FALSE(fs::exists(dir / "s" / "runs" / "chen_elliott_k2"));
  EXPECT_EQ(slurp(rec), before);
  const Csv csv = read_csv(dir / "s" / "sweep.csv");
  const RunRecord ref = read_record((dir / "s" / "records" / "reference.txt").string());
  const std::size_t row = csv.find("chen_elliott_k2");
  ASSERT_LT(row, csv.rows.size());
  EXPECT_NEAR(csv.num(row, "speedup"), ref.wall_time / 1000, 1e-15);
  EXPECT_NEAR(csv.num(row, "err_pile"),
              std::abs(45 - ref.values.at("pile")) / std::abs(ref.values.at("pile")), 1e-12);
  // A second start runs nothing.
  ASSERT_EQ(cgdem(args("--no-plots")), 0);
  EXPECT_NE(slurp(dir / "out.txt").find("3 runs (0 to do)"), std::string::npos) << slurp(dir / "out.txt");
}

TEST_F(SweepTest, KilledSweepResumes) {
  const fs::path ref = dir / "s" / "records" / "reference.txt";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string out = (dir / "s").string();
    execl(CGDEM_BINARY, CGDEM_BINARY, "sweep", kScene.c_str(), "--laws", "chen_elliott", "--k", "1,2,3",
          "--set", "time.end=0.05", "--out", out.c_str(), "--policy", "serial", "--threads", "1",
          "--no-plots", "--quiet", static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto start = std::chrono::steady_clock::now();
  while (!fs::exists(ref) && std::chrono::steady_clock::now() - start < std::chrono::seconds(120))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(fs::exists(ref));
  const std::string before = slurp(ref);
  int complete = 0;
  for (const auto& e : fs::directory_iterator(dir / "s" / "records"))
    complete += e.path().extension() == ".txt";
  ASSERT_EQ(cgdem(args("--no-plots")), 0) << slurp(dir / "out.txt");
  const std::string log = slurp(dir / "out.txt");
  EXPECT_NE(log.find("skip reference"), std::string::npos) << log;
  EXPECT_NE(log.find("3 runs (" + std::to_string(3 - complete) + " to do)"), std::string::npos) << log;
  EXPECT_EQ(slurp(ref), before);
  EXPECT_EQ(read_csv(dir / "s" / "sweep.csv").rows.size(), 3u);
}

// --seeds: one run per seed and case, each group's placement seeded by it (the runs differ), and
// summary.csv with the statistics of the records.
TEST_F(SweepTest, SeedsRunEveryCasePerSeedAndSummarize) {
  const fs::path s = dir / "s";
  ASSERT_EQ(cgdem("sweep '" + kScene + "' --laws chen_elliott --k 2 --set time.end=0.05 --out '" +
                  s.string() + "' --threads 2 --seeds 4,5 --reference-seeds 4,5 --no-plots"),
            0)
      << slurp(dir / "out.txt");
  std::vector<RunRecord> records;
  for (const char* run : {"reference_s4", "reference_s5", "chen_elliott_k2_s4", "chen_elliott_k2_s5"}) {
    records.push_back(read_record((s / "records" / (std::string(run) + ".txt")).string()));
    EXPECT_EQ(records.back().status, "ok") << run;
  }
  EXPECT_EQ(records[0].seed, 4);
  EXPECT_EQ(records[1].seed, 5);
  EXPECT_NE(records[0].values.at("bed"), records[1].values.at("bed")); // other packings
  EXPECT_NE(records[0].samples.at("speed"), records[1].samples.at("speed"));
  const Csv sum = read_csv(s / "summary.csv");
  ASSERT_EQ(sum.rows.size(), 2u);
  EXPECT_EQ(sum.rows[0].at("law"), "none");
  EXPECT_EQ(sum.num(0, "seeds"), 2);
  EXPECT_EQ(sum.num(1, "seeds"), 2);
  const auto cases = summarize_cases(records, {"pile", "bed", "floor_stress"});
  for (std::size_t c = 0; c < 2; ++c)
    for (const char* v : {"bed", "floor_stress"}) {
      EXPECT_NEAR(sum.num(c, std::string(v) + "_mean"), cases[c].values.at(v).mean,
                  1e-9 * std::abs(cases[c].values.at(v).mean));
      EXPECT_NEAR(sum.num(c, std::string(v) + "_sd"), cases[c].values.at(v).sd,
                  1e-9 * cases[c].values.at(v).sd);
    }
  // Per-run errors in sweep.csv are against the mean of the reference's seeds.
  const Csv csv = read_csv(s / "sweep.csv");
  const std::size_t row = csv.find("chen_elliott_k2_s5");
  ASSERT_LT(row, csv.rows.size());
  const double ref_bed = 0.5 * (records[0].values.at("bed") + records[1].values.at("bed"));
  EXPECT_NEAR(csv.num(row, "err_bed"), std::abs(records[3].values.at("bed") - ref_bed) / ref_bed, 1e-12);
  EXPECT_NE(slurp(dir / "out.txt").find("over the seeds"), std::string::npos);
}

// --checkpoint-every: a sweep killed in the middle of a run continues that run from its checkpoint when
// started again, and ends with the same figures as a sweep never interrupted (a restart is bitwise).
// Starts `cgdem sweep kScene --out out ARGS`, waits for `file` to appear and a few checkpoints more, and
// kills the sweep with SIGKILL.
static void kill_sweep_after(const fs::path& out, const std::vector<std::string>& args,
                             const fs::path& file) {
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::vector<std::string> a{CGDEM_BINARY, "sweep", kScene, "--out", out.string()};
    a.insert(a.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& x : a)
      argv.push_back(x.data());
    argv.push_back(nullptr);
    execv(CGDEM_BINARY, argv.data());
    _exit(127);
  }
  const auto start = std::chrono::steady_clock::now();
  while (!fs::exists(file) && std::chrono::steady_clock::now() - start < std::chrono::seconds(120))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::this_thread::sleep_for(std::chrono::milliseconds(300)); // a few checkpoints further
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(fs::exists(file));
}

static std::string quoted(const std::vector<std::string>& args) {
  std::string s;
  for (const auto& a : args)
    s += " '" + a + "'";
  return s;
}

TEST_F(SweepTest, KilledRunContinuesFromItsCheckpoint) {
  const fs::path s = dir / "s", whole = dir / "whole";
  const std::vector<std::string> common{
      "--laws", "chen_elliott", "--k", "2",          "--set",   "time.end=0.6",       "--policy",
      "serial", "--threads",    "1",   "--no-plots", "--quiet", "--checkpoint-every", "0.05"};
  kill_sweep_after(s, common, s / "runs" / "reference" / "run.checkpoint.h5");
  ASSERT_FALSE(fs::exists(s / "records" / "reference.txt")) << "the run ended before the kill: lengthen it";
  const std::string rest = quoted(common);
  ASSERT_EQ(cgdem("sweep '" + kScene + "' --out '" + s.string() + "'" + rest), 0) << slurp(dir / "out.txt");
  ASSERT_EQ(cgdem("sweep '" + kScene + "' --out '" + whole.string() + "'" + rest), 0)
      << slurp(dir / "out.txt");
  const RunRecord resumed = read_record((s / "records" / "reference.txt").string());
  const RunRecord uninterrupted = read_record((whole / "records" / "reference.txt").string());
  EXPECT_EQ(resumed.pieces, 2);
  EXPECT_EQ(uninterrupted.pieces, 1);
  EXPECT_TRUE(fs::exists(s / "runs" / "reference" / "run.part1.h5"));
  EXPECT_EQ(resumed.steps, uninterrupted.steps);
  EXPECT_EQ(resumed.particles, uninterrupted.particles);
  EXPECT_EQ(resumed.values, uninterrupted.values);
  EXPECT_EQ(resumed.samples, uninterrupted.samples);
  EXPECT_GT(resumed.wall_time, 0);
}

// A first stage killed after a checkpoint continues from it like a run, bitwise, and the piece killed
// (up to its last checkpoint) counts in the run's time: first_stage_pieces.txt holds it and
// first_stage_time.txt, the stage's share of the record's wall and CPU seconds, includes it.
TEST_F(SweepTest, KilledFirstStageContinuesAndCountsItsEarlierPiece) {
  const fs::path s = dir / "s", whole = dir / "whole";
  const std::vector<std::string> common{"--laws",
                                        "chen_elliott",
                                        "--k",
                                        "2",
                                        "--set",
                                        "time.end=0.45",
                                        "--policy",
                                        "serial",
                                        "--threads",
                                        "1",
                                        "--no-plots",
                                        "--quiet",
                                        "--checkpoint-every",
                                        "0.05",
                                        "--first-stage",
                                        "materials.beads.friction=0.01",
                                        "--first-stage",
                                        "time.end=0.4"};
  const fs::path run = s / "runs" / "reference";
  kill_sweep_after(s, common, run / "first_stage.checkpoint.h5");
  ASSERT_FALSE(fs::exists(run / "first_stage.done")) << "the first stage ended before the kill: lengthen it";
  ASSERT_EQ(cgdem("sweep '" + kScene + "' --out '" + s.string() + "'" + quoted(common)), 0)
      << slurp(dir / "out.txt");
  ASSERT_EQ(cgdem("sweep '" + kScene + "' --out '" + whole.string() + "'" + quoted(common)), 0)
      << slurp(dir / "out.txt");
  const RunRecord resumed = read_record((s / "records" / "reference.txt").string());
  const RunRecord uninterrupted = read_record((whole / "records" / "reference.txt").string());
  EXPECT_EQ(resumed.steps, uninterrupted.steps);
  ASSERT_EQ(resumed.values.size(), uninterrupted.values.size());
  for (const auto& [name, v] : uninterrupted.values) // bitwise, nan (a flat pile's fit) included
    EXPECT_TRUE(resumed.values.at(name) == v || (std::isnan(v) && std::isnan(resumed.values.at(name))))
        << name;
  std::ifstream pieces(run / "first_stage_pieces.txt");
  long first = -1, last = -1;
  double killed = 0;
  ASSERT_TRUE(pieces >> first >> last >> killed) << "no earlier piece of the first stage recorded";
  EXPECT_EQ(first, 0);
  EXPECT_GT(last, 0);
  EXPECT_GT(killed, 0);
  EXPECT_FALSE(pieces >> first); // one killed piece
  double stage_wall = 0, stage_cpu = 0;
  std::ifstream(run / "first_stage_time.txt") >> stage_wall >> stage_cpu;
  EXPECT_GT(stage_wall, killed);
  EXPECT_GT(stage_cpu, 0);
  EXPECT_GE(resumed.wall_time, stage_wall);
  EXPECT_FALSE(fs::exists(whole / "runs" / "reference" / "first_stage_pieces.txt"));
}

// --first-stage: every run first runs the scene with those overrides to their end (here a pour with
// almost no friction to 0.03 s), then continues from there with the scene as given. The records count the
// steps of both stages, the result differs from the one-stage sweep's, and a bad key of the first stage
// stops the sweep before any run.
TEST_F(SweepTest, FirstStageRunsBeforeTheSceneAsGiven) {
  const std::string common = " --laws chen_elliott --k 2 --set time.end=0.05 --policy serial --threads 1 "
                             "--no-plots --quiet";
  const fs::path staged = dir / "staged", plain = dir / "plain";
  ASSERT_EQ(cgdem("sweep '" + kScene + "' --out '" + staged.string() + "'" + common +
                  " --first-stage materials.beads.friction=0.01 --first-stage time.end=0.03"),
            0)
      << slurp(dir / "out.txt");
  ASSERT_EQ(cgdem("sweep '" + kScene + "' --out '" + plain.string() + "'" + common), 0)
      << slurp(dir / "out.txt");
  for (const char* run : {"reference", "chen_elliott_k2"}) {
    SCOPED_TRACE(run);
    EXPECT_TRUE(fs::exists(staged / "runs" / run / "first_stage.h5"));
    EXPECT_TRUE(fs::exists(staged / "runs" / run / "first_stage.done"));
    const RunRecord a = read_record((staged / "records" / (std::string(run) + ".txt")).string());
    const RunRecord b = read_record((plain / "records" / (std::string(run) + ".txt")).string());
    EXPECT_EQ(a.status, "ok");
    EXPECT_EQ(a.steps, b.steps); // both stages' steps, from the start
    EXPECT_EQ(a.particles, b.particles);
    EXPECT_NE(a.values, b.values); // the pour's low friction changed the pile
    EXPECT_GT(a.cpu_time, 0);
  }
  // The continuation started where the first stage ended: the two processes' steps add up to the record's.
  const std::string log = slurp(staged / "runs" / "reference" / "log.txt");
  std::vector<long> steps;
  const std::regex done("done: ([0-9]+) steps");
  for (auto it = std::sregex_iterator(log.begin(), log.end(), done); it != std::sregex_iterator(); ++it)
    steps.push_back(std::stol((*it)[1]));
  ASSERT_EQ(steps.size(), 2u) << log;
  EXPECT_GT(steps[0], 0);
  EXPECT_GT(steps[1], 0);
  EXPECT_EQ(steps[0] + steps[1], read_record((staged / "records" / "reference.txt").string()).steps);
  EXPECT_EQ(cgdem("sweep '" + kScene + "' --out '" + (dir / "bad").string() + "'" + common +
                  " --first-stage materials.beads.frictio=0.01"),
            2);
  EXPECT_NE(slurp(dir / "out.txt").find("frictio"), std::string::npos) << slurp(dir / "out.txt");
  EXPECT_FALSE(fs::exists(dir / "bad" / "runs"));
  EXPECT_EQ(cgdem("sweep '" + kScene + "' --out '" + (dir / "bad").string() + "'" + common +
                  " --first-stage materials.beads.friction=0.01"),
            2);
  EXPECT_NE(slurp(dir / "out.txt").find("--first-stage time.end="), std::string::npos)
      << slurp(dir / "out.txt");
}

// A failed run (non-zero exit, or a nan main figure) is listed as failed in sweep.csv and the summary and
// left out of the plots; a plot left without a finite point is not written. Every record is pre-created:
// the sweep runs nothing and builds the table and plots from the records alone.
TEST_F(SweepTest, FailedRunsListedAndLeftOutOfPlots) {
  const fs::path s = dir / "s", records = s / "records";
  RunRecord ref;
  ref.run = "reference";
  ref.law = "none";
  ref.status = "ok";
  ref.particles = 300;
  ref.steps = 100;
  ref.wall_time = 8;
  ref.mass = 1e-3;
  ref.values = {{"pile", 20}, {"pile_height", 0.004}, {"floor_stress", 1}, {"bed", 0.5}, {"speed", 0.1}};
  ref.samples["speed"] = {0, 0.1, 0.2};
  RunRecord k2 = ref, k3 = ref;
  k2.run = "chen_elliott_k2";
  k2.law = "chen_elliott";
  k2.k = 2;
  k2.particles = 38;
  k2.wall_time = 2;
  k2.mass = 1.09e-3; // a polydisperse-like mass deficit: floor_stress gets a mass-matched curve
  k2.values = {{"pile", 22}, {"pile_height", 0.0042}, {"floor_stress", 1.1}, {"bed", 0.52}, {"speed", 0.12}};
  k3.run = "chen_elliott_k3";
  k3.law = "chen_elliott";
  k3.k = 3;
  k3.status = "failed (exit 3)";
  k3.exit_code = 3;
  k3.particles = 0;
  k3.values.clear();
  k3.samples.clear();
  for (const auto& r : {ref, k2, k3})
    write_record((records / (r.run + ".txt")).string(), r);

  EXPECT_EQ(cgdem(args("")), 1) << slurp(dir / "out.txt"); // some run failed
  std::string log = slurp(dir / "out.txt");
  EXPECT_NE(log.find("3 runs (0 to do)"), std::string::npos) << log;
  Csv csv = read_csv(s / "sweep.csv");
  ASSERT_EQ(csv.rows.size(), 3u);
  std::size_t row = csv.find("chen_elliott_k3");
  ASSERT_LT(row, 3u);
  EXPECT_EQ(csv.rows[row].at("status"), "failed (exit 3)");
  EXPECT_EQ(csv.rows[row].at("exit_code"), "3");
  for (const char* c : {"pile", "err_pile", "err_mass_matched_pile", "speedup", "ks_speed"})
    EXPECT_EQ(csv.rows[row].at(c), "") << c;
  row = csv.find("chen_elliott_k2");
  EXPECT_EQ(csv.rows[row].at("status"), "ok");
  EXPECT_EQ(csv.rows[row].at("exit_code"), "0");
  EXPECT_NEAR(csv.num(row, "mass_ratio"), 1.09, 1e-12);
  EXPECT_NEAR(csv.num(row, "err_floor_stress"), 0.1, 1e-12);
  EXPECT_NEAR(csv.num(row, "err_mass_matched_floor_stress"), 1.1 / 1.09 - 1, 1e-12); // p = 1
  EXPECT_NEAR(csv.num(row, "err_mass_matched_pile"), 0.1, 1e-12);                    // p = 0
  EXPECT_NEAR(csv.num(row, "err_mass_matched_pile_height"), 0.0042 / (0.004 * std::cbrt(1.09)) - 1, 1e-12);
  // The summary names the failed run; the plots hold the reference and k2 only, all finite: speed-up
  // (reference + k2 wall time; no CPU times recorded) and error (4 panels x 2 points + the mass-matched
  // floor stress, 2 points).
  EXPECT_NE(log.find("chen_elliott_k3"), std::string::npos);
  EXPECT_NE(log.find("failed (exit 3): left out of the plots"), std::string::npos) << log;
  EXPECT_NE(log.find("cgdem sweep: failed: chen_elliott_k3"), std::string::npos) << log;
  EXPECT_NE(log.find("wrote speedup.png (2 points)"), std::string::npos) << log;
  EXPECT_NE(log.find("wrote error.png (10 points)"), std::string::npos) << log;
  EXPECT_GT(fs::file_size(s / "speedup.png"), 100u);
  EXPECT_GT(fs::file_size(s / "error.png"), 100u);

  // k2 now exits 0 with a nan main figure: failed too, and no plot has a finite point left.
  k2.values["pile"] = std::nan("");
  write_record((records / "chen_elliott_k2.txt").string(), k2);
  EXPECT_TRUE(std::isnan(read_record((records / "chen_elliott_k2.txt").string()).values.at("pile")));
  EXPECT_EQ(cgdem(args("")), 1) << slurp(dir / "out.txt");
  log = slurp(dir / "out.txt");
  csv = read_csv(s / "sweep.csv");
  row = csv.find("chen_elliott_k2");
  EXPECT_EQ(csv.rows[row].at("status"), "failed (nan: pile)");
  EXPECT_EQ(csv.rows[row].at("exit_code"), "0");
  EXPECT_EQ(csv.rows[row].at("err_pile"), "");
  EXPECT_NE(log.find("cgdem sweep: failed: chen_elliott_k2, chen_elliott_k3"), std::string::npos) << log;
  EXPECT_NE(log.find("speedup.png not written"), std::string::npos) << log;
  EXPECT_NE(log.find("error.png not written"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(s / "speedup.png")); // the earlier plots are removed, not left stale
  EXPECT_FALSE(fs::exists(s / "error.png"));
}

// The ordering Thakur's paper-scale runs confirm (sweeps/README.md, "Thakur with periodic sides", case
// II: constant adhesion f0): scaling f0 with k^2 keeps the bed's stress and unconfined strength, scaling
// it with k underestimates both and with k^3 (constant Bond number) overestimates them. Here on the small
// side-walled version of the protocol (sweeps/thakur_eepa.yaml, 900 against 267 particles at k = 1.5).
TEST_F(SweepTest, ThakurConstantAdhesionKeepsStrengthOnlyUnderF0SquaredScaling) {
  const fs::path s = dir / "s";
  ASSERT_EQ(
      cgdem("sweep '" CGDEM_SOURCE_DIR "/sweeps/thakur_eepa.yaml' --laws "
            "thakur,thakur_f0_linear,thakur_f0_cubic --k 1.5 --set materials.powder.eepa.k_adh=0 --out '" +
            s.string() + "' --threads 2 --policy parallel --no-plots --quiet"),
      0)
      << slurp(dir / "out.txt");
  auto value = [&](const std::string& run, const std::string& name) {
    const RunRecord r = read_record((s / "records" / (run + ".txt")).string());
    EXPECT_EQ(r.status, "ok") << run;
    return r.values.at(name);
  };
  for (const char* name : {"stress", "ucs"}) {
    const double ref = value("reference", name), squared = value("thakur_k1.5", name),
                 linear = value("thakur_f0_linear_k1.5", name), cubic = value("thakur_f0_cubic_k1.5", name);
    ASSERT_GT(ref, 0) << name;
    EXPECT_LT(linear, ref) << name;
    EXPECT_GT(cubic, ref) << name;
    const double err_squared = std::abs(squared - ref) / ref;
    EXPECT_LT(err_squared, (ref - linear) / ref) << name;
    EXPECT_LT(err_squared, (cubic - ref) / ref) << name;
  }
}

// Hu's Fig. 3 ordering: Method 1 (forces similar under l) keeps the original bed's stress, Methods 2
// and 3 overestimate it, Method 2 most (at the paper's cross-section, sweeps/results/
// hu_compression_paper_50mms: Method 1 +6.7 %, Method 3 +101 %, Method 2 +185 % at l = 2). Here on Hu's
// two-stage protocol in miniature (sweeps/tiny_compression.yaml: 3,000 originals against ~350 particles
// at l = 2).
TEST_F(SweepTest, HuCompressionMethodOneKeepsTheOriginalStress) {
  const fs::path s = dir / "s";
  ASSERT_EQ(cgdem("sweep '" CGDEM_SOURCE_DIR "/sweeps/tiny_compression.yaml' --laws "
                  "hu_method1,hu_method2,hu_method3 --k 2 --first-stage materials.glass.friction=0.01 "
                  "--first-stage time.end=0.15 --first-stage 'outlets.0.point=[0, 0, 0.0349]' --out '" +
                  s.string() + "' --threads 2 --policy parallel --no-plots --quiet"),
            0)
      << slurp(dir / "out.txt");
  auto value = [&](const std::string& run, const std::string& name) {
    const RunRecord r = read_record((s / "records" / (run + ".txt")).string());
    EXPECT_EQ(r.status, "ok") << run;
    return r.values.at(name);
  };
  const double ref = value("reference", "stress"), m1 = value("hu_method1_k2", "stress"),
               m2 = value("hu_method2_k2", "stress"), m3 = value("hu_method3_k2", "stress");
  for (const char* run : {"reference", "hu_method1_k2", "hu_method2_k2", "hu_method3_k2"})
    EXPECT_NEAR(value(run, "stress_strain"), 0.1, 1e-9) << run;
  ASSERT_GT(ref, 0);
  const double err1 = std::abs(m1 - ref) / ref;
  EXPECT_LT(err1, 0.15);
  EXPECT_GT(m3, ref * (1 + 2 * err1));
  EXPECT_GT(m2, m3);

  // The outlet's `particles` value is the record's own column: one column of that name, not two.
  const Csv csv = read_csv(s / "sweep.csv");
  std::set<std::string> names(csv.header.begin(), csv.header.end());
  EXPECT_EQ(names.size(), csv.header.size());
  EXPECT_EQ(csv.num(csv.find("reference"), "particles"), value("reference", "particles"));
}

// The ordering Chen's drum at the paper's size shows at 10 and 20 rpm (sweeps/results/chen_drum_paper_*):
// under Chen's law the coarse powder, whose packing is k times as strong (F_c ~ k^3 over a cross-section
// ~ k^2), carries 48-75 % more of its mass over the top on the adhesive wall than the original; with
// surface_energy_power 1 (F_c ~ k^2) it carries about the original's share (-9 %, +4 %). Here in the
// miniature drum (sweeps/tiny_drum.yaml: 871 originals against 109 at k = 2; too few coarse particles
// across, D/d = 12, for their bed's angle to mean anything, so only the carried mass is compared).
TEST_F(SweepTest, DrumCoarsePowderCarriesTheOriginalsShareOnlyWithPullOffPerCrossSectionKept) {
  const fs::path chen = dir / "chen", linear = dir / "linear";
  const std::string scene = "sweep '" CGDEM_SOURCE_DIR "/sweeps/tiny_drum.yaml' --laws chen_elliott --k 2 ";
  const std::string common = " --threads 2 --policy parallel --no-plots --quiet";
  ASSERT_EQ(cgdem(scene + "--out '" + chen.string() + "'" + common), 0) << slurp(dir / "out.txt");
  // The same reference serves both: its record makes the second sweep skip it.
  fs::create_directories(linear / "records");
  fs::copy_file(chen / "records" / "reference.txt", linear / "records" / "reference.txt");
  ASSERT_EQ(cgdem(scene + "--coarse-set surface_energy_power=1 --out '" + linear.string() + "'" + common), 0)
      << slurp(dir / "out.txt");
  auto carried = [&](const fs::path& s, const std::string& run) {
    const RunRecord r = read_record((s / "records" / (run + ".txt")).string());
    EXPECT_EQ(r.status, "ok") << run;
    EXPECT_GT(r.values.at("drum_angle_frames"), 0) << run;
    return r.values.at("drum_angle_carried_mean");
  };
  const double ref = carried(chen, "reference"), cubic = carried(chen, "chen_elliott_k2"),
               squared = carried(linear, "chen_elliott_k2");
  ASSERT_GT(ref, 0.05); // the original's wall does carry powder over the top
  EXPECT_GT(cubic, 1.4 * ref);
  EXPECT_LT(squared, cubic);
  EXPECT_LT(std::abs(squared - ref), 0.5 * (cubic - ref));
}
