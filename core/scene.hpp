#pragma once
// The scene description: what a YAML scene file says, after parsing and validation
// (drivers/scene_parser.cpp), in SI units. Plain host data; the engine builds its device state from it.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>
#include "core/triangle_mesh_data.hpp"

namespace cgdem {

using Vec3d = std::array<double, 3>;

struct DomainSpec {
  Vec3d lo{0, 0, 0};
  Vec3d hi{1, 1, 1};
  std::array<bool, 3> periodic{false, false, false};
};

struct MaterialSpec {
  std::string name;
  double density = 0;        // kg/m^3 (required for particle materials)
  double youngs_modulus = 0; // Pa
  double poisson_ratio = 0.3;
  double restitution = 1; // (0, 1]
  double friction = 0;    // sliding
  double rolling_friction = 0;
  double surface_energy = 0; // J/m^2 (JKR, DMT; the pair overrides and the scaling laws read it too)
  // The parameters of the contact-law components, by "<block>.<key>" (e.g. "eepa.k1", "capillary.
  // contact_angle"), in SI units (angles in radians). Each component declares its own, with their defaults
  // (models/material_parameters.hpp); a key the material does not give takes that default.
  std::map<std::string, double> law_parameters;

  double law_parameter(const std::string& key, double fallback) const {
    const auto it = law_parameters.find(key);
    return it == law_parameters.end() ? fallback : it->second;
  }
};

// Which compiled law a scene uses, component by component (models/contact_law.hpp).
struct ContactSpec {
  std::string normal = "hertz";       // hertz | linear | jkr | eepa
  std::string adhesion = "none";      // none | dmt | capillary
  std::string tangential = "mindlin"; // mindlin | none
  std::string rolling = "none";       // none | constant_torque | spring_dashpot
  bool wall_adhesion = true;          // false: particle-wall pairs get no surface energy / liquid
  // Full JKR: a bonded pair separates at delta_S (JKR theory, docs/physics.md), at the pull-off point
  // delta_C as LAMMPS' jkr model does, or as soon as the overlap is lost (Hu's JKR).
  std::string jkr_separation = "delta_s"; // delta_s | pull_off | contact_loss
  // Lever arm of tangential forces (and the contact point of the slip velocity): R - overlap/2
  // (contact_point) or R (radius, which makes Chen-Elliott's torque scaling k^4 exact); auto takes radius
  // under chen_elliott and contact_point otherwise (resolved_lever_arm in setup/materials.hpp).
  std::string lever_arm = "auto"; // auto | contact_point | radius
  // How the damping coefficient follows from the restitution (setup/restitution.hpp): restitution (the
  // rebound of an isolated collision equals the input e for every law) or beta_formula (Tsuji's
  // 2 sqrt(5/6) beta(e) for Hertz and JKR, as LIGGGHTS and EDEM do).
  std::string damping = "restitution"; // restitution | beta_formula
  // Adhesive pairs (JKR, DMT) under damping: restitution: the impact speed, in sticking velocities
  // sqrt(2 W_s / m*), at which an isolated collision rebounds with e (setup/restitution.hpp). 0: the limit of
  // impact speeds far above it (the damping of the non-adhesive law).
  double restitution_speed_ratio = 0;
  // Direct force scaling wrapping the whole law (models/scaling/direct_force_scaling.hpp): none |
  // hu_method1 | hu_method2 | hu_method3 | sakai. Not a YAML key: derived from the groups' coarse_grain.law
  // by effective_contact() (setup/scaling.hpp); the compiled name gets "@<method>".
  std::string scaling = "none";
};

// Overrides for one material pair (values < 0 mean "mixed from the two materials").
struct PairOverrideSpec {
  std::string material_a, material_b;
  double restitution = -1, friction = -1, rolling_friction = -1, surface_energy = -1;
};

struct CoarseGrainSpec {
  std::string law =
      "none"; // none | chen_elliott | bond | cohesion | thakur | hu_method1 | hu_method2 | hu_method3 | sakai
  double factor = 1;
  // Hu Method 1 only: the interparticle torque scales as l^torque_power (2: Hu eq 30; 3: rotational
  // similarity with t_S = l t_O). 0: the method's own exponent.
  int torque_power = 0;
  // chen_elliott, bond, cohesion: the surface energy scales as k^surface_energy_power instead of the law's
  // own exponent (2, 2, 1.6), so the pull-off force scales as k^(p+1); p = 1 keeps the pull-off force per
  // particle cross-section, hence a packing's cohesive strength (docs/coarse_graining.md). < 0: the law's.
  double surface_energy_power = -1;
};

struct SizeSpec {
  std::string distribution = "mono";      // mono | uniform | normal | lognormal
  double radius = 0;                      // mono
  double min_radius = 0, max_radius = 0;  // uniform, and truncation for normal/lognormal
  double mean_radius = 0, std_radius = 0; // normal, lognormal
};

struct PlacementSpec {
  std::string kind = "lattice";   // lattice | random_box | random_cylinder | file
  Vec3d lo{0, 0, 0}, hi{0, 0, 0}; // box (lattice, random_box)
  Vec3d center{0, 0, 0};          // cylinder base centre
  Vec3d axis{0, 0, 1};            // cylinder axis (unit), from the base centre towards the top
  double cylinder_radius = 0, cylinder_height = 0;
  double spacing = 0; // lattice spacing (default: largest diameter * 1.05)
  std::uint64_t seed = 1;
  std::string file; // CSV (id,x,y,z,radius[,density]) or HDF5 (a cgdem frame)
  // inlet: particles appear in the box lo..hi during the run, at `rate` particles/s or `mass_rate` kg/s
  // (of the particles as simulated) from `start`, every `every` s, until the group's count is in.
  double rate = 0, mass_rate = 0, start = 0, every = 0;
};

struct GroupSpec {
  std::string name;
  std::string material;
  long count = 0; // particles to place (file placement: all in the file when 0)
  SizeSpec size;  // of the ORIGINAL particles
  PlacementSpec placement;
  Vec3d velocity{0, 0, 0};
  double velocity_random = 0; // magnitude of random-direction velocity added (Hu periodic box)
  CoarseGrainSpec coarse_grain;
  std::string source_location; // "file:line" of the group in the scene (for error messages)
};

struct WallSpec {
  std::string name;
  std::string type = "plane"; // plane | cylinder | cone | mesh
  std::string material;
  Vec3d point{0, 0, 0};  // plane: a point on it (a bounded plane's centre); cylinder, cone: base centre
  Vec3d normal{0, 0, 1}; // plane: unit normal pointing into the particles
  Vec3d axis{0, 0, 1};   // cylinder, cone axis (unit)
  double radius = 0, length = 0; // cylinder radius; cone radius at point; plane: disk bound (0: none)
  double end_radius = 0;         // cone radius at point + length * axis
  double size[2] = {0, 0};       // plane: rectangle side lengths (0: none), the first along `edge`
  Vec3d edge{0, 0, 0};           // plane: direction of the rectangle's first side (zero: chosen)
  double orifice = 0;            // plane: radius of a hole around point (a bounded plane only)
  bool caps = false;             // cylinder end caps
  // mesh: the file as given (relative to the scene's directory) and resolved, its placement (scale, then
  // rotation in degrees about x, y, z in turn, then translation) and the triangles read from it.
  std::string file, file_path;
  double scale = 1;
  Vec3d rotate{0, 0, 0}, translate{0, 0, 0};
  std::shared_ptr<const TriangleMeshData> mesh;
  bool bounded() const { return type == "plane" && (radius > 0 || size[0] > 0); }
  // Largest distance of the wall's surface from its axis (the rim speed of a rotating wall).
  double reach_radius() const {
    if (type == "cone") return radius > end_radius ? radius : end_radius;
    if (type == "plane" && size[0] > 0) return 0.5 * std::sqrt(size[0] * size[0] + size[1] * size[1]);
    if (type == "mesh" && mesh) {
      double r2 = 0;
      for (const auto& v : mesh->vertices) {
        double rel[3], along = 0;
        for (int a = 0; a < 3; ++a)
          rel[a] = v[a] - point[a], along += rel[a] * axis[a];
        double d2 = 0;
        for (int a = 0; a < 3; ++a)
          d2 += (rel[a] - along * axis[a]) * (rel[a] - along * axis[a]);
        r2 = std::max(r2, d2);
      }
      return std::sqrt(r2);
    }
    return radius;
  }
  // Motion: translation velocity and rotation rate about the axis (rad/s), active in [start, stop).
  Vec3d velocity{0, 0, 0};
  double angular_velocity = 0;
  double motion_start = 0, motion_stop = 1e300;
  // Further translation segments (motion.then), each a constant velocity over [start, stop): a piston
  // that approaches fast, then loads, then unloads.
  struct Segment {
    Vec3d velocity{0, 0, 0};
    double start = 0, stop = 0;
    double until_force = 0; // > 0: the segment also ends once the particles push back this hard (N)
  };
  std::vector<Segment> then;
  static constexpr int kMaxThen = 3; // as Wall::kMaxThen on the device
  double motion_until_force = 0;     // the first motion's until_force (N; 0: none)
  // Oscillation (motion.oscillation): amplitude sin(2 pi frequency (t - start)) along a unit direction
  // over [start, stop), added to the segments (a vibrated container).
  struct Oscillation {
    double amplitude = 0, frequency = 0, start = 0, stop = 1e300;
    Vec3d direction{0, 0, 1};
  } oscillation;
  // Segment k of the motion (-1: the first motion, `velocity` from `start` to `stop`) as a Segment.
  Segment segment(int k) const {
    return k < 0 ? Segment{velocity, motion_start, motion_stop, motion_until_force} : then[std::size_t(k)];
  }
  // Ends segment k at time t (a force-triggered stop): the wall holds its position from then on until
  // its next segment starts.
  void end_segment(int k, double t) {
    if (k < 0)
      motion_stop = t;
    else
      then[std::size_t(k)].stop = t;
  }

  // Displacement from the time-0 position (host twin of Wall::offset).
  Vec3d displacement(double t) const {
    const auto span = [t](double a, double b) { return t < a ? 0.0 : (t < b ? t - a : b - a); };
    Vec3d d;
    const double m0 = span(motion_start, motion_stop);
    for (int a = 0; a < 3; ++a)
      d[a] = m0 * velocity[a];
    for (const Segment& s : then) {
      const double m = span(s.start, s.stop);
      for (int a = 0; a < 3; ++a)
        d[a] += m * s.velocity[a];
    }
    const double swing = oscillation.amplitude * std::sin(2 * M_PI * oscillation.frequency *
                                                          span(oscillation.start, oscillation.stop));
    for (int a = 0; a < 3; ++a)
      d[a] += swing * oscillation.direction[a];
    return d;
  }
  bool translates() const {
    bool any = velocity[0] != 0 || velocity[1] != 0 || velocity[2] != 0 || oscillation.amplitude != 0;
    for (const Segment& s : then)
      any = any || s.velocity[0] != 0 || s.velocity[1] != 0 || s.velocity[2] != 0;
    return any;
  }
};

// Particles whose centre enters the region leave the simulation (checked every `every` s): a box lo..hi,
// or the half-space behind a plane (the side opposite its normal).
struct OutletSpec {
  std::string name;
  std::string type = "plane"; // plane | box
  Vec3d point{0, 0, 0}, normal{0, 0, 1};
  Vec3d lo{0, 0, 0}, hi{0, 0, 0};
  double every = 0; // 0: the default of the run driver
};

struct TimeSpec {
  double end = 0;
  double step = 0;         // 0 = auto
  double fraction = 0.2;   // of the estimated stable step when auto
  bool force_step = false; // allow a given step above the stable estimate
  // Cap the auto step so JKR snap-in/snap-off jumps are resolved (v dt <= 2e-3 u: collision energy within
  // 1% of W_s). Off by default: for bulk flows it costs orders of magnitude in steps (docs/stability.md).
  bool resolve_adhesion = false;
};

struct OutputSpec {
  double every = 0; // simulated time between frames (0: only first and last)
  std::vector<std::string> fields{"position", "velocity", "angular_velocity", "radius", "mass",
                                  "group",    "id"};
  std::string file = "results.h5";
};

struct StopSpec {
  double kinetic_energy_below = -1; // stop when translational KE < this (J) after min_time
  double min_time = 0;
};

struct NeighbourSpec {
  double skin = -1; // absolute (m); < 0: skin_fraction * largest diameter
  double skin_fraction = 0.2;
  int reorder_every = 1;           // spatial reorder every N list builds (0: never)
  std::string force_pass = "auto"; // blocks | pairs | auto (EngineConfig::force_pass)
};

struct AnalysisSpec {
  std::string name;
  std::string type;
  std::map<std::string, std::string> params;
};

struct StabilitySpec {
  double max_overlap_fraction = 0.5; // overlap above this fraction of the smaller radius is a blow-up
  bool relax_initial_overlaps = false;
  double overlap_tolerance = 0.01; // initial overlap allowed, as a fraction of the smaller radius
};

struct Scene {
  std::string source_file;   // for error messages
  std::string resolved_yaml; // the scene after --set overrides (stored in the HDF5 root)
  DomainSpec domain;
  Vec3d gravity{0, 0, -9.81};
  std::vector<MaterialSpec> materials;
  ContactSpec contact;
  std::vector<PairOverrideSpec> pair_overrides;
  std::vector<GroupSpec> groups;
  std::vector<WallSpec> walls;
  std::vector<OutletSpec> outlets;
  TimeSpec time;
  OutputSpec output;
  StopSpec stop;
  NeighbourSpec neighbour;
  StabilitySpec stability;
  std::vector<AnalysisSpec> analyses;

  int material_index(const std::string& name) const {
    for (size_t i = 0; i < materials.size(); ++i)
      if (materials[i].name == name) return static_cast<int>(i);
    return -1;
  }
};

// Initial particles on the host, produced by drivers/particle_generation.cpp (or a restart).
struct ParticleSet {
  std::vector<std::int64_t> id;
  std::vector<Vec3d> position, velocity, angular_velocity;
  std::vector<double> radius, density;
  std::vector<int> material, group;
  // The last `pending` particles are not placed yet: an inlet adds them during the run, in order per group.
  std::size_t pending = 0;
  std::size_t size() const { return id.size(); }
};

} // namespace cgdem
