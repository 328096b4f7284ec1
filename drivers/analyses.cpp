#include "drivers/analyses.hpp"
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <unordered_map>
#include "drivers/scene_parser.hpp"

namespace cgdem {

namespace {

constexpr double kPi = 3.14159265358979323846;
using A3 = std::array<double, 3>;

double dot(const A3& a, const A3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
A3 cross(const A3& a, const A3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
A3 unit(const A3& a) {
  const double n = std::sqrt(dot(a, a));
  return n > 0 ? A3{a[0] / n, a[1] / n, a[2] / n} : a;
}

// ---- parameters: the strings of AnalysisSpec::params, with errors located at analyses.N.key ----
class Params {
public:
  Params(const Scene& s, const AnalysisSpec& a, std::size_t index) : scene_(s), spec_(a), index_(index) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what, const std::string& fix) const {
    throw SceneError(scene_error_message(scene_.source_file, path(key), what, fix));
  }
  std::string path(const std::string& key) const {
    return "analyses." + std::to_string(index_) + (key.empty() ? "" : "." + key);
  }
  bool has(const std::string& key) const { return spec_.params.count(key) > 0; }
  std::string str(const std::string& key, const std::string& fallback, bool required = false) const {
    used_.push_back(key);
    auto it = spec_.params.find(key);
    if (it == spec_.params.end()) {
      if (required)
        fail(key, "missing parameter '" + key + "' for analysis type " + spec_.type, fix_for(key));
      return fallback;
    }
    return it->second;
  }
  double num(const std::string& key, double fallback, bool required = false) const {
    const std::string s = str(key, "", required);
    if (s.empty() && !required && !has(key)) return fallback;
    return parse_number(key, s);
  }
  std::vector<double> list(const std::string& key, std::size_t n, const std::vector<double>& fallback,
                           bool required = false) const {
    const std::string s = str(key, "", required);
    if (!has(key)) return fallback;
    std::string body = s;
    if (!body.empty() && body.front() == '[') body = body.substr(1);
    if (!body.empty() && body.back() == ']') body.pop_back();
    std::vector<double> v;
    std::stringstream ss(body);
    std::string item;
    while (std::getline(ss, item, ','))
      v.push_back(parse_number(key, item));
    if (v.size() != n)
      fail(key, "expected a list of " + std::to_string(n) + " numbers, got '" + s + "'", fix_for(key));
    return v;
  }
  // Every given parameter must have been read (catches typos).
  void check_all_used() const {
    for (const auto& kv : spec_.params)
      if (std::find(used_.begin(), used_.end(), kv.first) == used_.end()) {
        std::string known;
        for (const auto& u : used_)
          known += (known.empty() ? "" : ", ") + u;
        fail(kv.first, "unknown parameter '" + kv.first + "' for analysis type " + spec_.type,
             "known parameters: " + known);
      }
  }
  const Scene& scene() const { return scene_; }
  const AnalysisSpec& spec() const { return spec_; }

  int group(const std::string& key) const {
    const std::string g = str(key, "");
    if (g.empty()) return -1;
    for (std::size_t i = 0; i < scene_.groups.size(); ++i)
      if (scene_.groups[i].name == g) return static_cast<int>(i);
    fail(key, "group '" + g + "' is not defined under groups",
         "give the name of a group or leave it out (all)");
  }
  const WallSpec& wall(const std::string& key) const {
    const std::string w = str(key, "", true);
    for (const auto& s : scene_.walls)
      if (s.name == w) return s;
    fail(key, "wall '" + w + "' is not defined under walls", "give the name of a wall of the scene");
  }

private:
  double parse_number(const std::string& key, const std::string& s) const {
    try {
      std::size_t used = 0;
      const double x = std::stod(s, &used);
      while (used < s.size() && std::isspace(static_cast<unsigned char>(s[used])))
        ++used;
      if (used == s.size()) return x;
    } catch (const std::exception&) {
    }
    fail(key, "expected a number, got '" + s + "'", fix_for(key));
  }
  std::string fix_for(const std::string& key) const {
    return "see docs/sweeps.md (analysis type " + spec_.type + ", parameter " + key + ")";
  }
  const Scene& scene_;
  const AnalysisSpec& spec_;
  std::size_t index_;
  mutable std::vector<std::string> used_;
};

std::vector<char> group_mask(const FrameData& f, int group) {
  std::vector<char> use;
  if (group < 0) return use;
  use.resize(f.size());
  for (std::size_t i = 0; i < f.size(); ++i)
    use[i] = i < f.group.size() && f.group[i] == group;
  return use;
}

double max_radius(const FrameData& f) {
  double r = 0;
  for (double x : f.radius)
    r = std::max(r, x);
  return r;
}

// A CSV file written by an analysis: truncated at the first write of the run, appended afterwards.
class CsvSink {
public:
  explicit CsvSink(std::string path, std::string header)
      : path_(std::move(path)), header_(std::move(header)) {}
  bool enabled() const { return !path_.empty(); }
  std::ofstream open() {
    std::ofstream out(path_, started_ ? std::ios::app : std::ios::trunc);
    if (!started_) out << header_ << "\n";
    started_ = true;
    out.precision(10);
    return out;
  }

private:
  std::string path_, header_;
  bool started_ = false;
};

// ---- the analyses ----

class AngleOfRepose : public Analysis {
public:
  AngleOfRepose(const Params& p) : Analysis(p.spec().name, p.spec().type) {
    const auto c = p.list("center", 2, {});
    if (!c.empty()) {
      fixed_center_ = true;
      cx_ = c[0];
      cy_ = c[1];
    }
    floor_given_ = p.has("floor");
    floor_ = p.num("floor", 0);
    bin_width_ = p.num("bin_width", 0);
    sectors_ = static_cast<int>(p.num("sectors", 8));
    const std::string stat = p.str("sector_statistic", "mean");
    if (stat != "mean" && stat != "median")
      p.fail("sector_statistic", "sector_statistic must be mean or median, got '" + stat + "'",
             "e.g. sector_statistic: median (robust to slumped sectors and loose skirts)");
    statistic_ = stat == "median" ? SectorStatistic::median : SectorStatistic::mean;
    const auto flank = p.list("flank", 2, {0.2, 0.8});
    lo_ = flank[0];
    hi_ = flank[1];
    group_ = p.group("group");
    if (sectors_ < 1) p.fail("sectors", "sectors must be >= 1", "give a positive integer, e.g. 8");
    if (!(0 <= lo_ && lo_ < hi_ && hi_ <= 1))
      p.fail("flank", "flank must be [lo, hi] with 0 <= lo < hi <= 1", "e.g. flank: [0.2, 0.8]");
  }
  void evaluate(const AnalysisInput& in, std::map<std::string, double>& out) override {
    const FrameData& f = in.frame;
    const auto use = group_mask(f, group_);
    double cx = cx_, cy = cy_, floor = floor_;
    std::size_t n = 0;
    double sx = 0, sy = 0, zmin = std::numeric_limits<double>::max();
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (!use.empty() && !use[i]) continue;
      sx += f.position[3 * i];
      sy += f.position[3 * i + 1];
      zmin = std::min(zmin, f.position[3 * i + 2] - f.radius[i]);
      ++n;
    }
    if (n == 0) return;
    if (!fixed_center_) cx = sx / n, cy = sy / n;
    if (!floor_given_) floor = zmin;
    const double w = bin_width_ > 0 ? bin_width_ : 4 * max_radius(f);
    const PileFit fit = pile_angle(f, use, cx, cy, floor, w, sectors_, lo_, hi_, statistic_);
    out[name()] = fit.angle_deg;
    out[name() + "_stderr"] = fit.angle_stderr_deg;
    out[name() + "_height"] = fit.height;
    out[name() + "_foot_radius"] = fit.foot_radius;
    out[name() + "_r2"] = fit.r2;
    out[name() + "_bins"] = double(fit.bins_used);
  }

protected:
  // A heap of fixed shape (the same angle): its lengths grow as the cube root of its mass, and so does the
  // number of radial bins of a fixed width; the angle and the fit quality do not depend on the mass.
  std::map<std::string, double> default_mass_exponents() const override {
    return {{"", 0},    {"_stderr", 0},    {"_height", 1.0 / 3}, {"_foot_radius", 1.0 / 3},
            {"_r2", 0}, {"_bins", 1.0 / 3}};
  }

private:
  bool fixed_center_ = false, floor_given_ = false;
  double cx_ = 0, cy_ = 0, floor_ = 0, bin_width_ = 0, lo_ = 0.2, hi_ = 0.8;
  int sectors_ = 8, group_ = -1;
  SectorStatistic statistic_ = SectorStatistic::mean;
};

// Stress on a plane wall and strain from its prescribed motion.
class WallStress : public Analysis {
public:
  WallStress(const Params& p, bool peak) : Analysis(p.spec().name, p.spec().type), peak_(peak) {
    const WallSpec& w = p.wall("wall");
    if (w.type != "plane")
      p.fail("wall", "wall '" + w.name + "' is a " + w.type + "; the stress needs a plane wall",
             "name a plane wall (a piston or plate)");
    wall_ = w;
    area_ = p.num("area", default_area(w, p.scene().domain));
    if (area_ <= 0)
      p.fail("area",
             p.has("area") ? "area must be > 0"
                           : "the wall's area is not defined (an infinite plane "
                             "whose normal is not along an axis)",
             "give the wall's loaded area in m^2");
    height_ = p.num("initial_height", 0);
    if (p.has("initial_height") && height_ <= 0)
      p.fail("initial_height", "initial_height must be > 0", "give the sample height in m, or leave it out");
    from_ = p.num("from", 0);
    if (from_ < 0) p.fail("from", "from must be >= 0", "give the time (s) the test starts, e.g. from: 0.5");
  }
  // The loaded area when none is given: a bounded plane's own (less its orifice), or for an infinite
  // plane along an axis the domain's cross-section across it (a piston filling a periodic box); 0 if
  // neither applies.
  static double default_area(const WallSpec& w, const DomainSpec& d) {
    if (w.bounded()) {
      const double face = w.size[0] > 0 ? w.size[0] * w.size[1] : kPi * w.radius * w.radius;
      return face - kPi * w.orifice * w.orifice;
    }
    for (int a = 0; a < 3; ++a)
      if (std::fabs(std::fabs(w.normal[a]) - 1) < 1e-12)
        return (d.hi[(a + 1) % 3] - d.lo[(a + 1) % 3]) * (d.hi[(a + 2) % 3] - d.lo[(a + 2) % 3]);
    return 0;
  }
  // Without initial_height: the sample's extent from the wall along its normal (to the farthest particle
  // edge) when the test starts, measured at the first output from `from` on.
  void measure_height(const AnalysisInput& in) {
    const Vec3d moved = wall_.displacement(in.time);
    double h = 0;
    for (std::size_t i = 0; i < in.frame.size(); ++i) {
      double s = in.frame.radius[i];
      for (int a = 0; a < 3; ++a)
        s += (in.frame.position[3 * i + a] - wall_.point[a] - moved[a]) * wall_.normal[a];
      h = std::max(h, s);
    }
    height_ = h;
  }
  // Strain counted from the wall's position at `from` (a piston that first approaches the sample); nan
  // until the sample height is known.
  double strain(double t) const {
    if (!(height_ > 0)) return std::numeric_limits<double>::quiet_NaN();
    const Vec3d d = wall_.displacement(std::max(t, from_)), d0 = wall_.displacement(from_);
    return (dot(d, wall_.normal) - dot(d0, wall_.normal)) / height_;
  }
  double stress(const AnalysisInput& in) const {
    for (std::size_t k = 0; k < in.wall_names.size(); ++k)
      if (in.wall_names[k] == wall_.name && in.wall_force.size() >= 3 * k + 3) {
        const A3 force{in.wall_force[3 * k], in.wall_force[3 * k + 1], in.wall_force[3 * k + 2]};
        return -dot(force, wall_.normal) / area_;
      }
    return std::numeric_limits<double>::quiet_NaN();
  }
  void evaluate(const AnalysisInput& in, std::map<std::string, double>& out) override {
    if (!(height_ > 0) && in.time >= from_) measure_height(in);
    const double s = stress(in), e = strain(in.time);
    if (!peak_) {
      out[name()] = s;
      out[name() + "_strain"] = e;
      return;
    }
    if (in.accumulate && in.time >= from_ && (s > peak_stress_ || !seen_)) {
      peak_stress_ = s;
      peak_strain_ = e;
      seen_ = true;
    }
    out[name()] = peak_stress_;
    out[name() + "_peak_strain"] = peak_strain_;
    out[name() + "_stress"] = s;
    out[name() + "_strain"] = e;
  }

protected:
  // wall_stress: the force of the sample on a wall of fixed area, as a floor carries its weight: p = 1.
  // unconfined_strength: the peak stress a sample of fixed cross-section withstands is a property of the
  // material and its packing, not of how much of it there is: p = 0. A strain-controlled compression
  // read through wall_stress is such a material response too: give it mass_exponent: 0.
  std::map<std::string, double> default_mass_exponents() const override {
    if (!peak_) return {{"", 1}, {"_strain", 0}};
    return {{"", 0}, {"_peak_strain", 0}, {"_stress", 0}, {"_strain", 0}};
  }

public:
  void wall_motion_changed(const WallSpec& w) override {
    if (w.name == wall_.name) wall_ = w;
  }
  std::vector<double> state() const override {
    return {height_, seen_ ? 1.0 : 0.0, peak_stress_, peak_strain_};
  }
  void restore_state(const std::vector<double>& s) override {
    expect_state(s, 4);
    height_ = s[0];
    seen_ = s[1] != 0;
    peak_stress_ = s[2];
    peak_strain_ = s[3];
  }

private:
  bool peak_;
  WallSpec wall_;
  double area_ = 0, height_ = 0, from_ = 0;
  bool seen_ = false;
  double peak_stress_ = 0, peak_strain_ = 0;
};

class ProfileAnalysis : public Analysis {
public:
  ProfileAnalysis(const Params& p)
      : Analysis(p.spec().name, p.spec().type),
        csv_(p.str("csv", ""), "time,bin,lo,hi,porosity,coordination,particles") {
    const std::string a = p.str("axis", "z");
    if (a == "x" || a == "0")
      axis_ = 0;
    else if (a == "y" || a == "1")
      axis_ = 1;
    else if (a == "z" || a == "2")
      axis_ = 2;
    else
      p.fail("axis", "axis must be x, y or z, got '" + a + "'", "e.g. axis: z");
    const auto& d = p.scene().domain;
    const auto r = p.list("region", 6, {d.lo[0], d.lo[1], d.lo[2], d.hi[0], d.hi[1], d.hi[2]});
    for (int k = 0; k < 3; ++k) {
      lo_[k] = r[k];
      hi_[k] = r[k + 3];
      if (!(hi_[k] > lo_[k]))
        p.fail("region", "region must be [xlo, ylo, zlo, xhi, yhi, zhi] with hi > lo", "");
    }
    bins_ = static_cast<int>(p.num("bins", 10));
    tolerance_ = p.num("contact_tolerance", 0.01);
    if (bins_ < 1) p.fail("bins", "bins must be >= 1", "e.g. bins: 10");
    if (tolerance_ < 0) p.fail("contact_tolerance", "contact_tolerance must be >= 0", "e.g. 0.01");
  }
  void evaluate(const AnalysisInput& in, std::map<std::string, double>& out) override {
    const Profile pr = axis_profile(in.frame, axis_, lo_, hi_, bins_, tolerance_);
    double pmin = 1, pmax = 0, cmin = std::numeric_limits<double>::max(), cmax = 0;
    for (int b = 0; b < bins_; ++b) {
      pmin = std::min(pmin, pr.porosity[b]);
      pmax = std::max(pmax, pr.porosity[b]);
      if (pr.particles[b] > 0) {
        cmin = std::min(cmin, pr.coordination[b]);
        cmax = std::max(cmax, pr.coordination[b]);
      }
    }
    if (cmin > cmax) cmin = cmax = 0;
    out[name()] = pr.porosity_total;
    out[name() + "_min"] = pmin;
    out[name() + "_max"] = pmax;
    out[name() + "_coordination"] = pr.coordination_mean;
    out[name() + "_coordination_min"] = cmin;
    out[name() + "_coordination_max"] = cmax;
    if (csv_.enabled()) {
      auto o = csv_.open();
      for (int b = 0; b < bins_; ++b)
        o << in.time << "," << b << "," << pr.lo[b] << "," << pr.hi[b] << "," << pr.porosity[b] << ","
          << pr.coordination[b] << "," << pr.particles[b] << "\n";
    }
  }

protected:
  // Porosity and coordination are intensive: a bed with more mass has more particles at the same packing.
  std::map<std::string, double> default_mass_exponents() const override {
    return {{"", 0},
            {"_min", 0},
            {"_max", 0},
            {"_coordination", 0},
            {"_coordination_min", 0},
            {"_coordination_max", 0}};
  }

private:
  CsvSink csv_;
  int axis_ = 2, bins_ = 10;
  A3 lo_{}, hi_{};
  double tolerance_ = 0.01;
};

class VelocityDistribution : public Analysis {
public:
  VelocityDistribution(const Params& p)
      : Analysis(p.spec().name, p.spec().type), csv_(p.str("csv", ""), "time,bin,lo,hi,pdf") {
    bins_ = static_cast<int>(p.num("bins", 30));
    max_ = p.num("max", 0);
    group_ = p.group("group");
    if (bins_ < 1) p.fail("bins", "bins must be >= 1", "e.g. bins: 30");
  }
  std::vector<double> samples(const FrameData& f) const override { return particle_speeds(f, group_); }
  bool is_distribution() const override { return true; }
  void evaluate(const AnalysisInput& in, std::map<std::string, double>& out) override {
    std::vector<double> v = samples(in.frame);
    if (v.empty()) return;
    std::sort(v.begin(), v.end());
    double mean = 0, sq = 0;
    for (double x : v)
      mean += x;
    mean /= v.size();
    for (double x : v)
      sq += (x - mean) * (x - mean);
    auto q = [&](double p) {
      return v[std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5))];
    };
    out[name()] = mean;
    out[name() + "_std"] = std::sqrt(sq / v.size());
    out[name() + "_median"] = q(0.5);
    out[name() + "_p90"] = q(0.9);
    out[name() + "_max"] = v.back();
    if (csv_.enabled()) {
      const double hi = max_ > 0 ? max_ : (v.back() > 0 ? v.back() : 1);
      const auto pdf = probability_density(v, 0, hi, bins_);
      auto o = csv_.open();
      for (int b = 0; b < bins_; ++b)
        o << in.time << "," << b << "," << hi * b / bins_ << "," << hi * (b + 1) / bins_ << "," << pdf[b]
          << "\n";
    }
  }

protected:
  // Speeds are set by what drives the flow (gravity over the scene's drop heights, a wall's speed), which
  // the sample's mass does not change: p = 0.
  std::map<std::string, double> default_mass_exponents() const override {
    return {{"", 0}, {"_std", 0}, {"_median", 0}, {"_p90", 0}, {"_max", 0}};
  }

private:
  CsvSink csv_;
  int bins_ = 30, group_ = -1;
  double max_ = 0;
};

class DrumAngle : public Analysis {
public:
  DrumAngle(const Params& p) : Analysis(p.spec().name, p.spec().type) {
    const WallSpec& w = p.wall("drum");
    if (w.type != "cylinder")
      p.fail("drum", "wall '" + w.name + "' is a " + w.type + "; the drum must be a cylinder wall",
             "name the drum's cylinder wall");
    center_ = w.point;
    axis_ = unit(w.axis);
    radius_ = w.radius;
    A3 g = p.scene().gravity;
    const double ga = dot(g, axis_);
    up_ = unit(A3{-(g[0] - ga * axis_[0]), -(g[1] - ga * axis_[1]), -(g[2] - ga * axis_[2])});
    if (dot(up_, up_) < 0.5)
      p.fail("drum", "gravity is parallel to the drum axis", "a drum needs gravity across its axis");
    cell_ = p.num("cell_width", 0);
    fraction_ = p.num("fit_fraction", 0.6);
    if (!(fraction_ > 0 && fraction_ <= 1))
      p.fail("fit_fraction", "fit_fraction must be in (0, 1]", "e.g. 0.6");
    bed_fraction_ = p.num("bed_fraction", 0.2);
    if (!(bed_fraction_ > 0 && bed_fraction_ < 1))
      p.fail("bed_fraction", "bed_fraction must be in (0, 1)", "the solid fraction of a bed cell, e.g. 0.2");
    wall_layer_ = p.num("wall_layer", 1.5);
    if (!(wall_layer_ >= 0))
      p.fail("wall_layer", "wall_layer must be >= 0", "the cells along the wall left out, e.g. 1.5");
    average_from_ = p.num("average_from", -1);
    if (p.has("average_from") && average_from_ < 0)
      p.fail("average_from", "average_from must be >= 0",
             "give the time (s) after the first avalanche, e.g. 1.0");
  }
  std::string metric() const override { return average_from_ < 0 ? name() : name() + "_mean"; }
  void evaluate(const AnalysisInput& in, std::map<std::string, double>& out) override {
    if (in.frame.size() == 0) return;
    const double cell = cell_ > 0 ? cell_ : 4 * max_radius(in.frame);
    const DrumFit fit =
        drum_angle(in.frame, center_, axis_, up_, radius_, cell, fraction_, bed_fraction_, wall_layer_);
    out[name()] = fit.angle_deg;
    out[name() + "_rms"] = fit.rms;
    out[name() + "_cells"] = double(fit.cells_used);
    out[name() + "_carried"] = fit.carried;
    if (average_from_ < 0) return;
    // A cohesive bed slumps: the angle of one frame depends on where in the avalanche cycle the run
    // stops, so the comparable figure is the mean over the output frames of the flowing regime. Each
    // frame time counts once (the final evaluation may repeat the last output frame).
    // A frame without a free surface (nan) adds nothing to the angle's mean: a run whose every frame
    // lacks one has a nan mean, which a sweep reports as failed rather than as a flat bed.
    if (in.accumulate && in.time >= average_from_ && in.time > last_time_) {
      if (std::isfinite(fit.angle_deg)) {
        sum_ += fit.angle_deg;
        sum_squares_ += fit.angle_deg * fit.angle_deg;
        ++frames_;
      }
      sum_carried_ += fit.carried;
      ++carried_frames_;
      last_time_ = in.time;
    }
    // Not yet defined before the first frame at or after average_from: nan, not 0, so that no plot or
    // sweep reads a zero angle.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double mean = frames_ > 0 ? sum_ / frames_ : nan;
    out[name() + "_mean"] = mean;
    // The frame-to-frame spread about that mean (sample standard deviation; nan below two frames).
    out[name() + "_std"] =
        frames_ > 1 ? std::sqrt(std::max(0.0, (sum_squares_ - frames_ * mean * mean) / (frames_ - 1))) : nan;
    out[name() + "_frames"] = double(frames_);
    out[name() + "_carried_mean"] = carried_frames_ > 0 ? sum_carried_ / carried_frames_ : nan;
  }

protected:
  // The dynamic angle of a drum of fixed size and speed depends on the fill level only weakly: p = 0.
  std::map<std::string, double> default_mass_exponents() const override {
    return {{"", 0},     {"_rms", 0},    {"_cells", 0},   {"_mean", 0},
            {"_std", 0}, {"_frames", 0}, {"_carried", 0}, {"_carried_mean", 0}};
  }

public:
  std::vector<double> state() const override {
    return {sum_, sum_squares_, last_time_, double(frames_), sum_carried_, double(carried_frames_)};
  }
  void restore_state(const std::vector<double>& s) override {
    expect_state(s, 6);
    sum_ = s[0];
    sum_squares_ = s[1];
    last_time_ = s[2];
    frames_ = std::lround(s[3]);
    sum_carried_ = s[4];
    carried_frames_ = std::lround(s[5]);
  }

private:
  A3 center_{}, axis_{0, 1, 0}, up_{0, 0, 1};
  double radius_ = 0, cell_ = 0, fraction_ = 0.6, bed_fraction_ = 0.2, wall_layer_ = 1.5, average_from_ = -1;
  double sum_ = 0, sum_squares_ = 0, last_time_ = -1, sum_carried_ = 0;
  long frames_ = 0, carried_frames_ = 0; // frames with a free surface; all frames of the window
};

// A flow or heap spreading along one axis: runout, front, height and free-surface angle (planar_flow).
class PlanarFlow : public Analysis {
public:
  PlanarFlow(const Params& p) : Analysis(p.spec().name, p.spec().type) {
    const std::string a = p.str("axis", "x");
    const std::string bare = !a.empty() && (a[0] == '-' || a[0] == '+') ? a.substr(1) : a;
    axis_ = bare == "x" ? 0 : bare == "y" ? 1 : bare == "z" ? 2 : -1;
    direction_ = !a.empty() && a[0] == '-' ? -1 : 1;
    if (axis_ < 0 || bare.size() != 1)
      p.fail("axis",
             "axis must be x, y or z, optionally signed (-x: the flow runs towards -x), got '" + a + "'",
             "e.g. axis: x");
    const std::string u = p.str("up", "z");
    up_ = u == "x" ? 0 : u == "y" ? 1 : u == "z" ? 2 : -1;
    if (up_ < 0 || up_ == axis_)
      p.fail("up", "up must be x, y or z and differ from the flow axis, got '" + u + "'", "e.g. up: z");
    origin_given_ = p.has("origin");
    origin_ = p.num("origin", 0);
    floor_given_ = p.has("floor");
    floor_ = p.num("floor", 0);
    bin_width_ = p.num("bin_width", 0);
    if (p.has("bin_width") && !(bin_width_ > 0))
      p.fail("bin_width", "bin_width must be > 0", "give a width in m, e.g. 4 particle radii");
    const auto flank = p.list("flank", 2, {0.2, 0.8});
    lo_ = flank[0];
    hi_ = flank[1];
    if (!(0 <= lo_ && lo_ < hi_ && hi_ <= 1))
      p.fail("flank", "flank must be [lo, hi] with 0 <= lo < hi <= 1", "e.g. flank: [0.2, 0.8]");
    group_ = p.group("group");
  }
  void evaluate(const AnalysisInput& in, std::map<std::string, double>& out) override {
    const FrameData& f = in.frame;
    const auto use = group_mask(f, group_);
    double back = std::numeric_limits<double>::max(), bottom = back;
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (!use.empty() && !use[i]) continue;
      back = std::min(back, direction_ * f.position[3 * i + axis_] - f.radius[i]);
      bottom = std::min(bottom, f.position[3 * i + up_] - f.radius[i]);
    }
    // Without an origin, the back of the particles at the first output (the column's back wall) is kept.
    if (!origin_given_ && !origin_set_ && back < std::numeric_limits<double>::max()) {
      origin_ = direction_ * back;
      origin_set_ = true;
    }
    const double w = bin_width_ > 0 ? bin_width_ : 4 * max_radius(f);
    const PlanarFlowFit fit =
        planar_flow(f, use, axis_, direction_, up_, origin_, floor_given_ ? floor_ : bottom, w, lo_, hi_);
    out[name()] = fit.runout;
    out[name() + "_front"] = fit.front;
    out[name() + "_height"] = fit.height;
    out[name() + "_angle"] = fit.angle_deg;
    out[name() + "_angle_stderr"] = fit.angle_stderr_deg;
    out[name() + "_r2"] = fit.r2;
    out[name() + "_bins"] = double(fit.bins_used);
  }

protected:
  // A planar flow or heap keeps its width (the channel's walls or periodic box): its mass grows with the
  // area of its cross-section, so a heap of fixed shape has lengths (runout, height, bins of a fixed
  // width) ~ mass^(1/2). The front is a coordinate, not a length (the runout is the length); the angle
  // and the fit quality do not depend on the mass.
  std::map<std::string, double> default_mass_exponents() const override {
    return {{"", 0.5},  {"_front", 0}, {"_height", 0.5}, {"_angle", 0}, {"_angle_stderr", 0},
            {"_r2", 0}, {"_bins", 0.5}};
  }

private:
public:
  std::vector<double> state() const override { return {origin_set_ ? 1.0 : 0.0, origin_}; }
  void restore_state(const std::vector<double>& s) override {
    expect_state(s, 2);
    origin_set_ = s[0] != 0;
    if (!origin_given_) origin_ = s[1];
  }

private:
  int axis_ = 0, direction_ = 1, up_ = 2, group_ = -1;
  bool origin_given_ = false, origin_set_ = false, floor_given_ = false;
  double origin_ = 0, floor_ = 0, bin_width_ = 0, lo_ = 0.2, hi_ = 0.8;
};

} // namespace

const std::vector<std::string>& analysis_types() {
  static const std::vector<std::string> t{"angle_of_repose", "wall_stress",           "unconfined_strength",
                                          "profile",         "velocity_distribution", "drum_angle",
                                          "planar_flow"};
  return t;
}

std::vector<std::unique_ptr<Analysis>> make_analyses(const Scene& scene) {
  std::vector<std::unique_ptr<Analysis>> list;
  for (std::size_t i = 0; i < scene.analyses.size(); ++i) {
    const AnalysisSpec& a = scene.analyses[i];
    Params p(scene, a, i);
    std::unique_ptr<Analysis> made;
    if (a.type == "angle_of_repose")
      made = std::make_unique<AngleOfRepose>(p);
    else if (a.type == "wall_stress")
      made = std::make_unique<WallStress>(p, false);
    else if (a.type == "unconfined_strength")
      made = std::make_unique<WallStress>(p, true);
    else if (a.type == "profile")
      made = std::make_unique<ProfileAnalysis>(p);
    else if (a.type == "velocity_distribution")
      made = std::make_unique<VelocityDistribution>(p);
    else if (a.type == "drum_angle")
      made = std::make_unique<DrumAngle>(p);
    else if (a.type == "planar_flow")
      made = std::make_unique<PlanarFlow>(p);
    else {
      std::string known, best;
      std::size_t best_d = 1000;
      for (const auto& t : analysis_types()) {
        known += (known.empty() ? "" : ", ") + t;
        const std::size_t d = edit_distance(a.type, t);
        if (d < best_d) best_d = d, best = t;
      }
      p.fail("type", "unknown analysis type '" + a.type + "'",
             (best_d <= 3 ? "did you mean '" + best + "'? " : std::string()) + "known types: " + known);
    }
    const double e = p.num("mass_exponent", 0); // read for every type, so that a typo's message lists it
    if (p.has("mass_exponent")) {
      if (!std::isfinite(e))
        p.fail("mass_exponent", "mass_exponent must be a finite number",
               "give p of value ~ mass^p, e.g. 0 for an angle, 1 for a force on a wall");
      made->set_mass_exponent(e);
    }
    p.check_all_used();
    list.push_back(std::move(made));
  }
  return list;
}

std::map<std::string, double> Analysis::mass_exponents() const {
  std::map<std::string, double> out;
  for (const auto& kv : default_mass_exponents())
    out[name_ + kv.first] = kv.second;
  if (main_exponent_set_) out[metric()] = out[name_] = main_exponent_;
  return out;
}

std::map<std::string, double> mass_exponents(const std::vector<std::unique_ptr<Analysis>>& analyses) {
  std::map<std::string, double> out;
  for (const auto& a : analyses)
    for (const auto& kv : a->mass_exponents())
      out.insert(kv);
  return out;
}

void Analysis::expect_state(const std::vector<double>& s, std::size_t n) const {
  if (s.size() != n)
    throw std::runtime_error("analysis '" + name_ + "' (" + type_ + "): checkpoint state of " +
                             std::to_string(s.size()) + " numbers, expected " + std::to_string(n));
}

void save_analysis_states(const std::vector<std::unique_ptr<Analysis>>& analyses, CheckpointData& c) {
  for (const auto& a : analyses)
    if (auto s = a->state(); !s.empty()) c.reals["analysis_" + a->name()] = std::move(s);
}

void load_analysis_states(std::vector<std::unique_ptr<Analysis>>& analyses, const CheckpointData& c) {
  for (auto& a : analyses) {
    if (a->state().empty()) continue;
    const auto it = c.reals.find("analysis_" + a->name());
    if (it == c.reals.end())
      throw std::runtime_error("checkpoint lacks the state of analysis '" + a->name() +
                               "' (written by a scene without it)");
    a->restore_state(it->second);
  }
}

void run_analyses(std::vector<std::unique_ptr<Analysis>>& analyses, const AnalysisInput& in,
                  std::map<std::string, double>& out) {
  for (auto& a : analyses)
    a->evaluate(in, out);
}

// ---- building blocks ----

// The standard error of atan(-slope), in degrees: d(atan s)/ds = 1 / (1 + s^2).
static double angle_stderr_deg(const LineFit& line) {
  return line.slope_stderr / (1 + line.slope * line.slope) * 180 / kPi;
}

LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  LineFit fit;
  fit.n = std::min(x.size(), y.size());
  if (fit.n < 2) return fit;
  Eigen::MatrixXd a(fit.n, 2);
  Eigen::VectorXd b(fit.n);
  for (std::size_t i = 0; i < fit.n; ++i) {
    a(i, 0) = 1;
    a(i, 1) = x[i];
    b(i) = y[i];
  }
  const Eigen::Vector2d c = a.colPivHouseholderQr().solve(b);
  fit.intercept = c(0);
  fit.slope = c(1);
  const double mean = b.mean();
  const double ss_tot = (b.array() - mean).square().sum();
  const double ss_res = (a * c - b).squaredNorm();
  fit.r2 = ss_tot > 0 ? 1 - ss_res / ss_tot : 1;
  const double sxx = (a.col(1).array() - a.col(1).mean()).square().sum();
  if (fit.n > 2 && sxx > 0) fit.slope_stderr = std::sqrt(ss_res / double(fit.n - 2) / sxx);
  return fit;
}

TiltFit fit_tilt(const std::vector<std::array<double, 2>>& points) {
  TiltFit fit;
  fit.n = points.size();
  if (fit.n < 2) return fit;
  double mx = 0, my = 0;
  for (const auto& p : points) {
    mx += p[0];
    my += p[1];
  }
  mx /= fit.n;
  my /= fit.n;
  double sxx = 0, syy = 0, sxy = 0;
  for (const auto& p : points) {
    sxx += (p[0] - mx) * (p[0] - mx);
    syy += (p[1] - my) * (p[1] - my);
    sxy += (p[0] - mx) * (p[1] - my);
  }
  sxx /= fit.n;
  syy /= fit.n;
  sxy /= fit.n;
  fit.angle_deg = std::abs(0.5 * std::atan2(2 * sxy, sxx - syy)) * 180 / kPi;
  const double smallest = 0.5 * (sxx + syy) - std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  fit.rms = std::sqrt(std::max(0.0, smallest));
  return fit;
}

PileFit pile_angle(const FrameData& f, const std::vector<char>& use, double cx, double cy, double floor,
                   double bin_width, int sectors, double lo_frac, double hi_frac, SectorStatistic statistic) {
  PileFit fit;
  const double lowest = -std::numeric_limits<double>::max();
  std::vector<std::vector<double>> top; // [radial bin][sector]
  double highest = lowest;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!use.empty() && !use[i]) continue;
    const double dx = f.position[3 * i] - cx, dy = f.position[3 * i + 1] - cy;
    const double t = f.position[3 * i + 2] + f.radius[i];
    const std::size_t rb = static_cast<std::size_t>(std::sqrt(dx * dx + dy * dy) / bin_width);
    int sec = static_cast<int>((std::atan2(dy, dx) + kPi) / (2 * kPi) * sectors);
    sec = std::min(std::max(sec, 0), sectors - 1);
    if (rb >= top.size()) top.resize(rb + 1, std::vector<double>(sectors, lowest));
    top[rb][sec] = std::max(top[rb][sec], t);
    highest = std::max(highest, t);
  }
  if (highest == lowest) return fit;
  fit.height = highest - floor;
  std::vector<double> r, h;
  std::vector<double> tops;
  for (std::size_t b = 0; b < top.size(); ++b) {
    tops.clear();
    for (double t : top[b])
      if (t > lowest) tops.push_back(t);
    if (tops.empty()) continue;
    double surface = 0;
    if (statistic == SectorStatistic::median) {
      std::sort(tops.begin(), tops.end());
      const std::size_t m = tops.size() / 2;
      surface = tops.size() % 2 == 1 ? tops[m] : 0.5 * (tops[m - 1] + tops[m]);
    } else {
      for (double t : tops)
        surface += t;
      surface /= static_cast<double>(tops.size());
    }
    const double s = surface - floor;
    if (s < lo_frac * fit.height || s > hi_frac * fit.height) continue;
    r.push_back((b + 0.5) * bin_width);
    h.push_back(s);
  }
  const LineFit line = fit_line(r, h);
  fit.bins_used = line.n;
  if (line.n < 2) return fit;
  fit.angle_deg = std::atan(-line.slope) * 180 / kPi;
  fit.angle_stderr_deg = angle_stderr_deg(line);
  fit.r2 = line.r2;
  fit.foot_radius = line.slope < 0 ? -line.intercept / line.slope : 0;
  return fit;
}

PlanarFlowFit planar_flow(const FrameData& f, const std::vector<char>& use, int axis, int direction, int up,
                          double origin, double floor, double bin_width, double lo_frac, double hi_frac) {
  PlanarFlowFit fit;
  const int across = 3 - axis - up;
  const double lowest = -std::numeric_limits<double>::max();
  std::map<long, std::map<long, double>> top; // [bin along the flow][strip across]: highest top
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!use.empty() && !use[i]) continue;
    const double s = direction * (f.position[3 * i + axis] - origin);
    const long b = static_cast<long>(std::floor(s / bin_width));
    const long c = static_cast<long>(std::floor(f.position[3 * i + across] / bin_width));
    double& t = top[b].try_emplace(c, lowest).first->second;
    t = std::max(t, f.position[3 * i + up] + f.radius[i] - floor);
  }
  if (top.empty()) return fit;
  std::map<long, double> height; // mean over the strips
  for (const auto& [b, strips] : top) {
    double sum = 0;
    for (const auto& kv : strips)
      sum += kv.second;
    height[b] = sum / static_cast<double>(strips.size());
  }
  long peak = height.begin()->first;
  for (const auto& [b, h] : height)
    if (h > height[peak]) peak = b;
  long last = peak;
  while (height.count(last + 1))
    ++last;
  fit.height = height[peak];
  double front = lowest;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (!use.empty() && !use[i]) continue;
    const double s = direction * (f.position[3 * i + axis] - origin);
    if (static_cast<long>(std::floor(s / bin_width)) <= last) front = std::max(front, s + f.radius[i]);
  }
  fit.runout = front;
  fit.front = origin + direction * front;
  std::vector<double> x, y;
  for (long b = peak; b <= last; ++b) {
    const double h = height[b];
    if (h >= lo_frac * fit.height && h <= hi_frac * fit.height) {
      x.push_back((b + 0.5) * bin_width);
      y.push_back(h);
    }
  }
  const LineFit line = fit_line(x, y);
  fit.bins_used = line.n;
  if (line.n < 2) return fit;
  fit.angle_deg = std::atan(-line.slope) * 180 / kPi;
  fit.angle_stderr_deg = angle_stderr_deg(line);
  fit.r2 = line.r2;
  return fit;
}

DrumFit drum_angle(const FrameData& f, const std::array<double, 3>& center, const std::array<double, 3>& axis,
                   const std::array<double, 3>& up, double drum_radius, double cell_width,
                   double fit_fraction, double bed_fraction, double wall_layer) {
  DrumFit fit;
  if (f.size() == 0) return fit;
  const A3 eu = cross(up, axis);
  // The cross-section seen along the axis, in square cells of cell_width: each cell's solid volume and the
  // top (v + r) of its highest particle.
  struct Cell {
    double volume = 0, top = -std::numeric_limits<double>::max();
  };
  std::map<long, std::map<long, Cell>> columns; // u cell -> v cell -> cell
  double wmin = std::numeric_limits<double>::max(), wmax = -wmin;
  double mass = 0, mass_above = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const A3 d{f.position[3 * i] - center[0], f.position[3 * i + 1] - center[1],
               f.position[3 * i + 2] - center[2]};
    const double u = dot(d, eu), v = dot(d, up), w = dot(d, axis), r = f.radius[i];
    wmin = std::min(wmin, w - r);
    wmax = std::max(wmax, w + r);
    const double m = f.mass.size() == f.size() ? f.mass[i] : r * r * r;
    mass += m;
    if (v > 0) mass_above += m;
    Cell& c =
        columns[static_cast<long>(std::floor(u / cell_width))][static_cast<long>(std::floor(v / cell_width))];
    c.volume += 4.0 / 3.0 * kPi * r * r * r;
    c.top = std::max(c.top, v + r);
  }
  // A cell is bed when its solid fraction over the occupied length reaches bed_fraction. Each column's
  // surface is the top of the run of bed cells rising from its lowest one; what lies above a gap (powder
  // coating the wall over the bed, a cohesive powder carried over the top, particles in flight) is not the
  // surface. Surfaces within wall_layer cells of the drum wall are the coating on the wall beside the bed.
  const double cell_volume = cell_width * cell_width * (wmax - wmin);
  const double inner = drum_radius - wall_layer * cell_width;
  fit.carried = mass > 0 ? mass_above / mass : 0;
  std::vector<std::array<double, 2>> surface;
  for (const auto& column : columns) {
    long top_cell = 0;
    bool found = false;
    for (const auto& cell : column.second) { // ascending v
      const bool bed = cell.second.volume >= bed_fraction * cell_volume;
      if (!found && bed) {
        found = true;
        top_cell = cell.first;
      } else if (found && bed && cell.first == top_cell + 1) {
        top_cell = cell.first;
      } else if (found) {
        break;
      }
    }
    if (!found) continue;
    const double u = (column.first + 0.5) * cell_width, v = column.second.at(top_cell).top;
    if (u * u + v * v < inner * inner) surface.push_back({u, v});
  }
  if (surface.empty()) return fit;
  double umin = surface[0][0], umax = umin;
  for (const auto& p : surface) {
    umin = std::min(umin, p[0]);
    umax = std::max(umax, p[0]);
  }
  const double mid = 0.5 * (umin + umax), half = 0.5 * fit_fraction * (umax - umin);
  std::vector<std::array<double, 2>> pts;
  for (const auto& p : surface)
    if (std::abs(p[0] - mid) <= half) pts.push_back(p);
  const TiltFit line = fit_tilt(pts);
  fit.cells_used = line.n;
  if (line.n < 2) return fit;
  fit.angle_deg = line.angle_deg;
  fit.rms = line.rms;
  return fit;
}

double wasserstein1(std::vector<double> a, std::vector<double> b) {
  if (a.empty() || b.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  // Integral of |F_a - F_b| over the merged support.
  std::size_t i = 0, j = 0;
  double x = std::min(a[0], b[0]), w1 = 0;
  while (i < a.size() || j < b.size()) {
    const double next = j >= b.size() || (i < a.size() && a[i] <= b[j]) ? a[i] : b[j];
    w1 += std::abs(double(i) / a.size() - double(j) / b.size()) * (next - x);
    x = next;
    while (i < a.size() && a[i] == next)
      ++i;
    while (j < b.size() && b[j] == next)
      ++j;
  }
  return w1;
}

double ks_distance(std::vector<double> a, std::vector<double> b) {
  if (a.empty() || b.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  std::size_t i = 0, j = 0;
  double d = 0;
  while (i < a.size() || j < b.size()) {
    const double next = j >= b.size() || (i < a.size() && a[i] <= b[j]) ? a[i] : b[j];
    while (i < a.size() && a[i] == next)
      ++i;
    while (j < b.size() && b[j] == next)
      ++j;
    d = std::max(d, std::abs(double(i) / a.size() - double(j) / b.size()));
  }
  return d;
}

std::vector<double> quantile_samples(std::vector<double> v, std::size_t max_size) {
  std::sort(v.begin(), v.end());
  if (v.size() <= max_size || max_size < 2) return v;
  // Midpoint quantiles (k + 0.5) / m with linear interpolation: each stands for an equal share of the sample.
  std::vector<double> q(max_size);
  for (std::size_t k = 0; k < max_size; ++k) {
    const double pos = (k + 0.5) / max_size * v.size() - 0.5;
    const std::size_t lo = static_cast<std::size_t>(std::max(0.0, std::floor(pos)));
    const std::size_t hi = std::min(v.size() - 1, lo + 1);
    const double t = std::min(1.0, std::max(0.0, pos - lo));
    q[k] = v[lo] + t * (v[hi] - v[lo]);
  }
  return q;
}

std::vector<double> particle_speeds(const FrameData& f, int group) {
  std::vector<double> s;
  if (f.velocity.size() < 3 * f.size()) return s;
  s.reserve(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (group >= 0 && (i >= f.group.size() || f.group[i] != group)) continue;
    const double* v = &f.velocity[3 * i];
    s.push_back(std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
  }
  return s;
}

std::vector<double> probability_density(const std::vector<double>& v, double lo, double hi, int bins) {
  std::vector<double> pdf(std::max(bins, 1), 0.0);
  if (v.empty() || !(hi > lo)) return pdf;
  const double w = (hi - lo) / bins;
  for (double x : v) {
    if (x < lo || x > hi) continue;
    const int b = std::min(bins - 1, static_cast<int>((x - lo) / w));
    pdf[b] += 1;
  }
  for (double& p : pdf)
    p /= v.size() * w;
  return pdf;
}

double sphere_segment_volume(double r, double a, double b) {
  a = std::max(a, -r);
  b = std::min(b, r);
  if (b <= a) return 0;
  return kPi * (r * r * (b - a) - (b * b * b - a * a * a) / 3);
}

Profile axis_profile(const FrameData& f, int axis, const std::array<double, 3>& lo,
                     const std::array<double, 3>& hi, int bins, double contact_tolerance) {
  Profile p;
  const double len = (hi[axis] - lo[axis]) / bins;
  double area = 1;
  for (int k = 0; k < 3; ++k)
    if (k != axis) area *= hi[k] - lo[k];
  p.lo.resize(bins);
  p.hi.resize(bins);
  p.porosity.assign(bins, 0);
  p.coordination.assign(bins, 0);
  p.particles.assign(bins, 0);
  for (int b = 0; b < bins; ++b) {
    p.lo[b] = lo[axis] + b * len;
    p.hi[b] = lo[axis] + (b + 1) * len;
  }
  const std::size_t n = f.size();
  // Contacts per particle: hashed cell grid of width 2 r_max (1 + tolerance).
  const double rmax = max_radius(f);
  std::vector<int> contacts(n, 0);
  if (n > 0 && rmax > 0) {
    const double cell = 2 * rmax * (1 + contact_tolerance);
    auto key = [&](long x, long y, long z) { return (x * 73856093L) ^ (y * 19349663L) ^ (z * 83492791L); };
    std::unordered_multimap<long, std::size_t> grid;
    std::vector<std::array<long, 3>> c(n);
    for (std::size_t i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k)
        c[i][k] = static_cast<long>(std::floor(f.position[3 * i + k] / cell));
      grid.emplace(key(c[i][0], c[i][1], c[i][2]), i);
    }
    for (std::size_t i = 0; i < n; ++i)
      for (long dx = -1; dx <= 1; ++dx)
        for (long dy = -1; dy <= 1; ++dy)
          for (long dz = -1; dz <= 1; ++dz) {
            const long cx = c[i][0] + dx, cy = c[i][1] + dy, cz = c[i][2] + dz;
            auto range = grid.equal_range(key(cx, cy, cz));
            for (auto it = range.first; it != range.second; ++it) {
              const std::size_t j = it->second;
              if (j <= i || c[j][0] != cx || c[j][1] != cy || c[j][2] != cz) continue;
              double d2 = 0;
              for (int k = 0; k < 3; ++k) {
                const double d = f.position[3 * i + k] - f.position[3 * j + k];
                d2 += d * d;
              }
              const double gap = std::sqrt(d2) - f.radius[i] - f.radius[j];
              if (gap < contact_tolerance * std::min(f.radius[i], f.radius[j])) ++contacts[i], ++contacts[j];
            }
          }
  }
  double solid_total = 0;
  long in_region = 0, contact_sum = 0;
  std::vector<double> solid(bins, 0);
  for (std::size_t i = 0; i < n; ++i) {
    bool lateral = true;
    for (int k = 0; k < 3; ++k)
      if (k != axis) lateral = lateral && f.position[3 * i + k] >= lo[k] && f.position[3 * i + k] <= hi[k];
    if (!lateral) continue;
    const double x = f.position[3 * i + axis], r = f.radius[i];
    const int b0 = std::max(0, static_cast<int>(std::floor((x - r - lo[axis]) / len)));
    const int b1 = std::min(bins - 1, static_cast<int>(std::floor((x + r - lo[axis]) / len)));
    for (int b = b0; b <= b1; ++b) {
      const double v = sphere_segment_volume(r, p.lo[b] - x, p.hi[b] - x);
      solid[b] += v;
      solid_total += v;
    }
    if (x < lo[axis] || x > hi[axis]) continue;
    const int b = std::min(bins - 1, static_cast<int>((x - lo[axis]) / len));
    ++p.particles[b];
    p.coordination[b] += contacts[i];
    ++in_region;
    contact_sum += contacts[i];
  }
  for (int b = 0; b < bins; ++b) {
    p.porosity[b] = 1 - solid[b] / (area * len);
    if (p.particles[b] > 0) p.coordination[b] /= p.particles[b];
  }
  p.porosity_total = 1 - solid_total / (area * len * bins);
  p.coordination_mean = in_region > 0 ? double(contact_sum) / in_region : 0;
  return p;
}

} // namespace cgdem
