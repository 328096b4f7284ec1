#pragma once
// On-the-fly analyses of a run (the scene's `analyses:` list, docs/sweeps.md): host-side computations on
// the frame copy the engine hands to the writer at every output. Each analysis adds a few scalars to the
// series row (/series/<name>, /series/<name>_<extra> in the HDF5 file); the first, /series/<name>, is its
// main figure (the one a sweep compares). Some also append full profiles or distributions to a CSV file.
//
// Types and their main figure:
//   angle_of_repose       static angle of a pile (degrees): least-squares line through the surface heights
//                         of radial bins on the flank; extras: height, foot radius, r2, bins
//   wall_stress           normal stress on a plane wall (Pa, compression positive) = -F.n / area;
//                         extras: strain (wall displacement along its normal / initial height)
//   unconfined_strength   peak of wall_stress so far (Pa); extras: strain at the peak, current stress, strain
//   profile               porosity of a box region (slabs along an axis); extras: min/max slab porosity,
//                         mean coordination number and its slab min/max
//   velocity_distribution mean speed (m/s); extras: std, median, p90, max; optional CSV of the PDF
//   drum_angle            dynamic angle of repose in a rotating drum (degrees): total least-squares line
//                         through the bed's free surface seen along the axis (not the powder coating the
//                         wall above it); extras: the mass fraction carried above the axis
//   planar_flow           runout of a flow or heap spreading along one axis (column collapse, slump, planar
//                         heap; m); extras: front position, height, free-surface angle, r2, bins
// The building blocks (fits, distances, profiles) are exposed for the unit tests and the sweep.
#include <array>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>
#include "core/frame.hpp"
#include "core/scene.hpp"

namespace cgdem {

// What an analysis sees at one output.
struct AnalysisInput {
  const FrameData& frame;
  double time = 0;
  const std::vector<std::string>& wall_names;
  const std::vector<double>& wall_force; // 3 per named wall: the force the particles exert on it
  // false for a frame the uninterrupted run does not output (a restart between outputs): evaluated, but
  // kept out of running means and peaks.
  bool accumulate = true;
};

class Analysis {
public:
  Analysis(std::string name, std::string type) : name_(std::move(name)), type_(std::move(type)) {}
  virtual ~Analysis() = default;
  const std::string& name() const { return name_; }
  const std::string& type() const { return type_; }
  // Adds this analysis' outputs (name, name_<extra>) to `out`.
  virtual void evaluate(const AnalysisInput& in, std::map<std::string, double>& out) = 0;
  // Distribution analyses: the samples whose distribution they describe (speeds); others: empty.
  virtual std::vector<double> samples(const FrameData&) const { return {}; }
  virtual bool is_distribution() const { return false; }
  // The output a sweep compares against the reference and plots: the main value unless the analysis'
  // parameters make another one the meaningful figure (a drum's mean angle over the flowing regime).
  virtual std::string metric() const { return name_; }
  // How each output (full name) scales with the mass of the sample, everything else in the scene fixed:
  // value ~ mass^p. A sweep corrects the reference to a coarse run's mass with it (err_mass_matched_<value>
  // in sweep.csv, docs/sweeps.md). The scene's `mass_exponent` parameter replaces p of the main figure.
  std::map<std::string, double> mass_exponents() const;
  void set_mass_exponent(double p) { main_exponent_ = p, main_exponent_set_ = true; }
  // What the analysis has accumulated over earlier outputs (a running mean or peak, a height or origin
  // measured at the first output), saved in checkpoints so that a restarted run reports what the
  // uninterrupted one would. Empty for analyses of the current frame alone. restore_state throws
  // std::runtime_error on a state of the wrong size.
  // A wall's motion as it now is (a segment ended early by its until_force), for the analyses that
  // follow a wall's prescribed position.
  virtual void wall_motion_changed(const WallSpec&) {}
  virtual std::vector<double> state() const { return {}; }
  virtual void restore_state(const std::vector<double>& s) { expect_state(s, 0); }

protected:
  void expect_state(const std::vector<double>& s, std::size_t n) const;

protected:
  // The type's own exponents, keyed by output suffix ("" for the main figure, "_height", ...).
  virtual std::map<std::string, double> default_mass_exponents() const = 0;

private:
  std::string name_, type_;
  double main_exponent_ = 0;
  bool main_exponent_set_ = false;
};

const std::vector<std::string>& analysis_types();
// Builds the scene's analyses; throws SceneError (one line naming analyses.N.key and the fix) on an unknown
// type, a missing or malformed parameter, or a wall that does not exist.
std::vector<std::unique_ptr<Analysis>> make_analyses(const Scene& scene);
// The mass exponents of every output of `analyses` (Analysis::mass_exponents).
std::map<std::string, double> mass_exponents(const std::vector<std::unique_ptr<Analysis>>& analyses);
// Evaluates them all into `out`.
void run_analyses(std::vector<std::unique_ptr<Analysis>>& analyses, const AnalysisInput& in,
                  std::map<std::string, double>& out);
// The accumulated state of every analysis with one, as /reals/analysis_<name> of a checkpoint, and back.
// load_analysis_states throws std::runtime_error when the checkpoint lacks a state the scene's analyses
// need (a checkpoint of another scene) or holds one of the wrong size.
void save_analysis_states(const std::vector<std::unique_ptr<Analysis>>& analyses, CheckpointData& c);
void load_analysis_states(std::vector<std::unique_ptr<Analysis>>& analyses, const CheckpointData& c);

// ---- building blocks ----

struct LineFit {
  double slope = 0, intercept = 0, r2 = 0;
  double slope_stderr = std::numeric_limits<double>::quiet_NaN(); // from the residuals; nan for n < 3
  std::size_t n = 0;
};
// Ordinary least squares y = intercept + slope x (Eigen); n < 2 gives a zero fit with n set.
LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y);

struct TiltFit {
  double angle_deg = 0; // the line's tilt from the x axis, 0-90 degrees
  double rms = 0;       // rms distance of the points from the line
  std::size_t n = 0;
};
// Total least squares line through the points (x, y): the principal axis of their covariance. n < 2 gives
// a zero fit with n set.
TiltFit fit_tilt(const std::vector<std::array<double, 2>>& points);

struct PileFit {
  double angle_deg = 0, height = 0, foot_radius = 0, r2 = 0;
  double angle_stderr_deg =
      std::numeric_limits<double>::quiet_NaN(); // the slope's standard error, as an angle
  std::size_t bins_used = 0;
};
// How a radial bin's sectors make its surface height: their mean, or their median, which a few slumped
// sectors or a loose skirt (a rough pile of few large particles) do not drag down.
enum class SectorStatistic { mean, median };
// Pile on a floor at z = floor, around the vertical axis through (cx, cy). Particles `use` (all when empty)
// are binned radially (width bin_width) and azimuthally (sectors); the surface height of a radial bin is the
// mean (or median) over its non-empty sectors of the highest particle top (z + r). height = the highest
// top - floor. The flank is the radial bins whose surface height is within [lo_frac, hi_frac] x height; the
// fit of surface height against the bin's radius there gives the angle atan(-slope).
PileFit pile_angle(const FrameData& f, const std::vector<char>& use, double cx, double cy, double floor,
                   double bin_width, int sectors, double lo_frac, double hi_frac,
                   SectorStatistic statistic = SectorStatistic::mean);

struct DrumFit {
  // nan until defined: fewer than 2 surface points in the fitted range (no bed, or a bed turning as a lump
  // with no free surface below the wall layer)
  double angle_deg = std::numeric_limits<double>::quiet_NaN(), rms = std::numeric_limits<double>::quiet_NaN();
  std::size_t cells_used = 0;
  double carried = 0; // mass fraction whose centres lie above the drum's axis
};
// Bed in a drum of radius drum_radius: axis through `center` along `axis`, `up` = the upward direction
// (perpendicular to the axis). The cross-section seen along the axis (u = up x axis, v = up) in square
// cells of cell_width; a cell is bed when its solid fraction over the particles' length along the axis is
// at least bed_fraction. Each u column's surface point is the top (v + r) of the highest particle in the
// run of bed cells rising from its lowest one, so that powder stuck to the wall above the bed (a cohesive
// powder coats the drum and is carried over the top) or in flight is not read as the surface; points
// within wall_layer cells of the drum wall are that coating beside the bed and are dropped. The points whose
// u lies in the central `fit_fraction` of their u range are fitted with a total least squares line; the angle
// is its tilt, rms its residual, cells_used the points fitted. `carried` is the share of the mass above the
// axis: powder stuck to the wall and carried over the top (a bed filled up to 0.5 lies below the axis).
DrumFit drum_angle(const FrameData& f, const std::array<double, 3>& center, const std::array<double, 3>& axis,
                   const std::array<double, 3>& up, double drum_radius, double cell_width,
                   double fit_fraction, double bed_fraction = 0.2, double wall_layer = 1.5);

struct PlanarFlowFit {
  // nan until defined: no particles, or (angle, r2) fewer than 2 flank bins
  double runout = std::numeric_limits<double>::quiet_NaN();    // front - origin along the flow, m
  double front = std::numeric_limits<double>::quiet_NaN();     // front position on the flow axis, m
  double height = std::numeric_limits<double>::quiet_NaN();    // highest surface height above the floor, m
  double angle_deg = std::numeric_limits<double>::quiet_NaN(); // free-surface angle beyond the peak
  double angle_stderr_deg = std::numeric_limits<double>::quiet_NaN(); // its standard error (3+ flank bins)
  double r2 = std::numeric_limits<double>::quiet_NaN();
  std::size_t bins_used = 0;
};
// A flow or heap spreading along `axis` (0, 1, 2) in the direction `direction` (+1 or -1) from `origin` (the
// gate or back wall's coordinate on that axis), heights along `up` over a floor at `floor`. Particles `use`
// (all when empty) are binned along the flow (width bin_width, s = direction (x - origin)) and across it (the
// third axis, strips of the same width); the surface height of a bin is the mean over its non-empty strips
// of the highest particle top (up + r) - floor. Walking from the highest bin in the flow direction, the flow
// ends before the first empty bin, so that particles thrown ahead of it do not move the front: the front is
// the farthest particle edge (s + r) in the bins up to there. The free-surface angle is atan(-slope) of the
// least-squares line through the surface heights of the bins from the peak to the front whose height is
// within [lo_frac, hi_frac] x height.
PlanarFlowFit planar_flow(const FrameData& f, const std::vector<char>& use, int axis, int direction, int up,
                          double origin, double floor, double bin_width, double lo_frac, double hi_frac);

// Distances between the empirical distributions of two samples (any order, any sizes > 0).
double wasserstein1(std::vector<double> a, std::vector<double> b);
double ks_distance(std::vector<double> a, std::vector<double> b);
// Sorted copy; when longer than max_size, max_size evenly spaced quantiles (a faithful, bounded record).
std::vector<double> quantile_samples(std::vector<double> v, std::size_t max_size);
// Speeds |v| of the particles of a group (group < 0: all).
std::vector<double> particle_speeds(const FrameData& f, int group);
// Probability density of `v` on `bins` equal bins of [lo, hi] (values outside are left out of the counts
// but not of the normalisation: the density integrates to the fraction inside).
std::vector<double> probability_density(const std::vector<double>& v, double lo, double hi, int bins);

struct Profile {
  std::vector<double> lo, hi;       // slab bounds along the axis
  std::vector<double> porosity;     // 1 - solid volume / slab volume
  std::vector<double> coordination; // mean contacts per particle with its centre in the slab (0 if none)
  std::vector<long> particles;      // particles with their centre in the slab
  double porosity_total = 1;        // of the whole region
  double coordination_mean = 0;     // over the particles in the region
};
// Slabs of the box region [lo, hi] along `axis` (0, 1, 2). Solid volume: each sphere whose centre lies in
// the region's lateral bounds contributes the exact spherical segment inside each slab (its lateral
// overhang is not clipped). Contacts: pairs with gap |xi - xj| - ri - rj below tolerance x the smaller
// radius (all particles count as partners, inside the region or not). Periodic images are not considered.
Profile axis_profile(const FrameData& f, int axis, const std::array<double, 3>& lo,
                     const std::array<double, 3>& hi, int bins, double contact_tolerance);
// Volume of the part of a sphere of radius r (centred at 0) between the planes z = a and z = b.
double sphere_segment_volume(double r, double a, double b);

} // namespace cgdem
