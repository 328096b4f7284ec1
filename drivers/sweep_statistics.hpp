#pragma once
// Seed-to-seed statistics of a sweep run with --seeds: every (law, k) case is run once per seed of the
// initial packing, and a case's figures are the mean and standard deviation over its seeds.
//
// The reference against which each run's error is computed is the mean over the reference's seeds
// (mean_record). A case "matches" the reference in a value when the difference of the means is within the
// seed-to-seed scatter of that difference, sqrt(sd_case^2 + sd_ref^2): the spread of one run of the case
// minus one run of the reference. With one seed on either side only the other side's spread is counted;
// with one seed on both sides there is no scatter and no verdict (within is nan), nor for the reference.
#include <map>
#include <string>
#include <vector>
#include "drivers/sweep_command.hpp"

namespace cgdem {

struct SampleStats {
  int n = 0;
  double mean = 0, sd = 0; // sd: sample standard deviation (n - 1), 0 for one sample
};
SampleStats sample_stats(const std::vector<double>& x); // the finite entries of x

// A record standing for several runs of one case: mean wall and CPU time, mass, particle count and step
// count, the mean of each value over the runs where it is finite, the samples of every run pooled. Its
// exit code is the first non-zero one of the runs (0 when all succeeded).
RunRecord mean_record(const std::vector<RunRecord>& runs, const std::string& name);

struct CaseSummary {
  std::string law;
  double k = 1;
  int seeds = 0;                       // runs of the case that succeeded
  long particles = 0;                  // of the first run
  double speedup = 0, speedup_cpu = 0; // mean reference time / mean case time
  std::map<std::string, SampleStats> values;
  std::map<std::string, double> error;   // (mean - mean_ref) / |mean_ref| (signed; the difference when 0)
  std::map<std::string, double> scatter; // sqrt(sd^2 + sd_ref^2), relative like error
  std::map<std::string, double> within;  // 1 when |error| <= scatter, 0 when not, nan without scatter
};

// One summary per (law, k) in the order of first appearance, the reference ("none", k = 1) first. Runs
// with a non-zero exit code are left out of their case's statistics.
std::vector<CaseSummary> summarize_cases(const std::vector<RunRecord>& runs,
                                         const std::vector<std::string>& values);

// summary.csv: law, k, seeds, particles, speedup, speedup_cpu, then per value <v>_mean, <v>_sd, err_<v>,
// scatter_<v>, within_<v>. Written atomically (temporary file, rename).
void write_summary_csv(const std::string& path, const std::vector<CaseSummary>& cases,
                       const std::vector<std::string>& values);

} // namespace cgdem
