// Writes the CSV files behind validation/results (figures: validation/plot_scaling.py): Chen & Elliott's
// cases a (head-on), b (oblique wall impact) and c (normal wall impact against speed) and the critical
// sticking velocity, for every coarse-graining law at k = 1, 2, 4 (1-8 for the sticking velocity). The
// cases are built by tests/test_scaling_support.hpp, the same code the ctest assertions run.
//
//   build/validation/write_scaling_csv [OUT_DIR]      (default validation/results; ~2 minutes)
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>
#include "drivers/kokkos_session.hpp"
#include "tests/test_scaling_support.hpp"

using namespace cgdem;
using namespace cgdem::testing;

namespace {

const char* const kLaws[] = {"chen_elliott", "bond",       "cohesion", "hu_method1",
                             "hu_method2",   "hu_method3", "sakai"};

struct CsvFile {
  std::FILE* f;
  explicit CsvFile(const std::string& path) : f(std::fopen(path.c_str(), "w")) {
    if (!f) throw std::runtime_error("cannot write " + path);
  }
  ~CsvFile() { std::fclose(f); }
};

void case_a(const std::string& dir) {
  CsvFile series(dir + "/case_a_series.csv"), summary(dir + "/case_a_summary.csv");
  std::fprintf(series.f, "law,k,time,velocity,overlap,force_over_Fc\n");
  std::fprintf(summary.f,
               "law,k,restitution,contact_time,max_overlap,max_attraction_over_Fc,max_repulsion_over_Fc\n");
  for (const char* law : kLaws)
    for (double k : {1.0, 2.0, 4.0}) {
      ImpactSpec c = chen_case_a(law, k);
      c.record = true;
      c.max_contact_times = 30 * k;
      const ImpactOutcome o = run_impact(c);
      long n = 0;
      for (const ImpactSample& q : o.series)
        if (n++ % 4 == 0)
          std::fprintf(series.f, "%s,%g,%.9g,%.9g,%.9g,%.9g\n", law, k, q.time, q.velocity / c.speed,
                       q.overlap, q.force / o.F_c);
      std::fprintf(summary.f, "%s,%g,%.9g,%.9g,%.9g,%.9g,%.9g\n", law, k, o.restitution, o.contact_time,
                   o.max_overlap, o.max_attraction, o.max_repulsion);
    }
}

// Case b under every law with the default lever arm (auto: R under Chen-Elliott, R - delta/2 otherwise),
// Chen-Elliott also with R - delta/2, and Hu Method 1 with both torque powers (2: Hu eq 30; 3).
void case_b(const std::string& dir) {
  CsvFile series(dir + "/case_b_series.csv"), summary(dir + "/case_b_summary.csv");
  std::fprintf(series.f,
               "law,lever_arm,torque_power,k,time,normal_velocity,tangential_velocity,omega_times_k,"
               "tangential_force_over_Fc,normal_force_over_Fc,overlap,tangential_stiffness_over_k3\n");
  std::fprintf(summary.f, "law,lever_arm,torque_power,k,restitution,contact_time,max_overlap,"
                          "tangential_velocity_after,omega_times_k_after\n");
  struct Variant {
    const char* lever;
    int torque_power;
  };
  for (const char* law : kLaws) {
    std::vector<Variant> variants = {{"auto", 0}};
    if (std::string(law) == "chen_elliott") variants.push_back({"contact_point", 0});
    if (std::string(law) == "hu_method1") variants.push_back({"auto", 3});
    for (const Variant& variant : variants) {
      const char* lever = variant.lever;
      for (double k : {1.0, 2.0, 4.0}) {
        ImpactSpec c = chen_case_b(law, k);
        c.record = true;
        c.lever_arm = lever;
        c.torque_power = variant.torque_power;
        c.max_contact_times = 60 * k;
        const ImpactOutcome o = run_impact(c);
        const double kk = std::string(law) == "none" ? 1.0 : k, k3 = kk * kk * kk;
        for (const ImpactSample& q : o.series)
          std::fprintf(series.f, "%s,%s,%d,%g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", law, lever,
                       variant.torque_power, k, q.time, q.velocity, q.tangential_velocity, q.omega * kk,
                       q.tangential_force / o.F_c, q.force / o.F_c, q.overlap, q.tangential_stiffness / k3);
        std::fprintf(summary.f, "%s,%s,%d,%g,%.9g,%.9g,%.9g,%.9g,%.9g\n", law, lever, variant.torque_power, k,
                     o.restitution, o.contact_time, o.max_overlap, o.tangential_after, o.omega * kk);
      }
    }
  }
}

void case_c(const std::string& dir) {
  CsvFile f(dir + "/case_c_sweep.csv");
  std::fprintf(f.f, "law,k,speed,restitution,contact_time,max_overlap,stuck\n");
  for (const char* law : kLaws)
    for (double k : {1.0, 2.0, 4.0})
      for (double v : {0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 13.0, 16.0, 20.0}) {
        ImpactSpec c = chen_case_c(law, k, v);
        c.max_contact_times = 60 * k;
        const ImpactOutcome o = run_impact(c);
        std::fprintf(f.f, "%s,%g,%g,%.9g,%.9g,%.9g,%d\n", law, k, v, o.restitution, o.contact_time,
                     o.max_overlap, o.stuck ? 1 : 0);
      }
}

void sticking(const std::string& dir) {
  CsvFile f(dir + "/sticking_velocity.csv");
  std::fprintf(f.f, "law,k,sticking_velocity\n");
  for (const char* law : kLaws)
    for (double k : {1.0, 2.0, 3.0, 4.0, 6.0, 8.0}) {
      ImpactSpec c = chen_case_c(law, k, 1);
      c.max_contact_times = 60 * k;
      std::fprintf(f.f, "%s,%g,%.6g\n", law, k, sticking_velocity(c, 0.02, 30, 2e-3));
      std::fflush(f.f);
    }
}

} // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "validation/results";
  if (argc > 2 || dir == "--help" || dir == "-h") {
    std::printf("usage: write_scaling_csv [OUT_DIR]   (default validation/results)\n");
    return argc > 2 ? 2 : 0;
  }
  std::filesystem::create_directories(dir);
  KokkosSession kokkos(1);
  const std::pair<const char*, void (*)(const std::string&)> cases[] = {
      {"case a", case_a}, {"case b", case_b}, {"case c", case_c}, {"sticking velocity", sticking}};
  for (const auto& [name, run] : cases) {
    std::printf("%s ...\n", name);
    std::fflush(stdout);
    run(dir);
  }
  std::printf("wrote %s/{case_a_series,case_a_summary,case_b_series,case_b_summary,case_c_sweep,"
              "sticking_velocity}.csv\n",
              dir.c_str());
  return 0;
}
