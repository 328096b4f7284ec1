#include "drivers/sweep_statistics.hpp"
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace cgdem {

SampleStats sample_stats(const std::vector<double>& x) {
  SampleStats s;
  double sum = 0;
  for (double v : x)
    if (std::isfinite(v)) sum += v, ++s.n;
  if (s.n == 0) {
    s.mean = s.sd = std::nan("");
    return s;
  }
  s.mean = sum / s.n;
  double ss = 0;
  for (double v : x)
    if (std::isfinite(v)) ss += (v - s.mean) * (v - s.mean);
  s.sd = s.n > 1 ? std::sqrt(ss / (s.n - 1)) : 0.0;
  return s;
}

RunRecord mean_record(const std::vector<RunRecord>& runs, const std::string& name) {
  RunRecord m;
  m.run = name;
  if (runs.empty()) return m;
  m.law = runs.front().law;
  m.k = runs.front().k;
  m.threads = runs.front().threads;
  m.particles = runs.front().particles;
  m.time_step = runs.front().time_step;
  m.status = "ok";
  for (const auto& r : runs)
    if (r.exit_code != 0) {
      m.exit_code = r.exit_code;
      m.status = r.status;
      return m;
    }
  auto mean_of = [&](auto get) {
    std::vector<double> x;
    for (const auto& r : runs)
      x.push_back(get(r));
    return sample_stats(x).mean;
  };
  m.wall_time = mean_of([](const RunRecord& r) { return r.wall_time; });
  m.cpu_time = mean_of([](const RunRecord& r) { return r.cpu_time; });
  m.mass = mean_of([](const RunRecord& r) { return r.mass; });
  m.steps = std::lround(mean_of([](const RunRecord& r) { return double(r.steps); }));
  m.particle_steps_per_s = mean_of([](const RunRecord& r) { return r.particle_steps_per_s; });
  m.engine_particle_steps_per_s = mean_of([](const RunRecord& r) { return r.engine_particle_steps_per_s; });
  for (const auto& r : runs)
    for (const auto& kv : r.values)
      m.values[kv.first] = 0;
  for (auto& kv : m.values)
    kv.second = mean_of([&](const RunRecord& r) {
      auto it = r.values.find(kv.first);
      return it == r.values.end() ? std::nan("") : it->second;
    });
  for (const auto& r : runs)
    for (const auto& kv : r.samples)
      m.samples[kv.first].insert(m.samples[kv.first].end(), kv.second.begin(), kv.second.end());
  return m;
}

std::vector<CaseSummary> summarize_cases(const std::vector<RunRecord>& runs,
                                         const std::vector<std::string>& values) {
  std::vector<std::pair<std::string, double>> order{{"none", 1.0}};
  std::map<std::pair<std::string, double>, std::vector<const RunRecord*>> by_case;
  for (const auto& r : runs) {
    const auto key = std::make_pair(r.law, r.k);
    if (!by_case.count(key) && key != order.front()) order.push_back(key);
    if (r.exit_code == 0) by_case[key].push_back(&r);
  }
  auto stats = [&](const std::vector<const RunRecord*>& rs, const std::string& v) {
    std::vector<double> x;
    for (const RunRecord* r : rs) {
      auto it = r->values.find(v);
      x.push_back(it == r->values.end() ? std::nan("") : it->second);
    }
    return sample_stats(x);
  };
  auto mean_time = [](const std::vector<const RunRecord*>& rs, bool cpu) {
    std::vector<double> x;
    for (const RunRecord* r : rs)
      x.push_back(cpu ? r->cpu_time : r->wall_time);
    return sample_stats(x).mean;
  };
  const auto& ref = by_case[order.front()];
  std::vector<CaseSummary> out;
  for (const auto& key : order) {
    const auto& rs = by_case[key];
    CaseSummary c;
    c.law = key.first;
    c.k = key.second;
    c.seeds = static_cast<int>(rs.size());
    c.particles = rs.empty() ? 0 : rs.front()->particles;
    c.speedup = rs.empty() || ref.empty() ? std::nan("") : mean_time(ref, false) / mean_time(rs, false);
    c.speedup_cpu = rs.empty() || ref.empty() ? std::nan("") : mean_time(ref, true) / mean_time(rs, true);
    for (const auto& v : values) {
      const SampleStats s = stats(rs, v), r = stats(ref, v);
      c.values[v] = s;
      const double scale = r.mean != 0 ? std::fabs(r.mean) : 1.0;
      c.error[v] = (s.mean - r.mean) / scale;
      const bool spread = (s.n > 1 || r.n > 1) && key != order.front(); // no verdict on the reference
      c.scatter[v] = spread ? std::sqrt(s.sd * s.sd + r.sd * r.sd) / scale : std::nan("");
      c.within[v] = spread && std::isfinite(c.error[v]) ? (std::fabs(c.error[v]) <= c.scatter[v] ? 1.0 : 0.0)
                                                        : std::nan("");
    }
    out.push_back(c);
  }
  return out;
}

void write_summary_csv(const std::string& path, const std::vector<CaseSummary>& cases,
                       const std::vector<std::string>& values) {
  auto num = [](double x) {
    if (!std::isfinite(x)) return std::string();
    char b[40];
    std::snprintf(b, sizeof b, "%.10g", x);
    return std::string(b);
  };
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << "law,k,seeds,particles,speedup,speedup_cpu";
    for (const auto& v : values)
      out << "," << v << "_mean," << v << "_sd,err_" << v << ",scatter_" << v << ",within_" << v;
    out << "\n";
    for (const auto& c : cases) {
      out << c.law << "," << num(c.k) << "," << c.seeds << "," << c.particles << "," << num(c.speedup) << ","
          << num(c.speedup_cpu);
      for (const auto& v : values) {
        const SampleStats& s = c.values.at(v);
        out << "," << num(s.mean) << "," << num(s.sd) << "," << num(c.error.at(v)) << ","
            << num(c.scatter.at(v)) << "," << num(c.within.at(v));
      }
      out << "\n";
    }
  }
  std::filesystem::rename(tmp, path);
}

} // namespace cgdem
