#include "drivers/inlets_outlets.hpp"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include "drivers/host_cell_grid.hpp"
#include "drivers/random.hpp"

namespace cgdem {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kTriesPerParticle = 60;

double sphere_mass(double density, double r) {
  return density * 4.0 / 3.0 * kPi * r * r * r;
}

// Appends particle k of `from` to `to`, every field.
void append_particle(ParticleSet& to, const ParticleSet& from, std::size_t k) {
  to.id.push_back(from.id[k]);
  to.position.push_back(from.position[k]);
  to.velocity.push_back(from.velocity[k]);
  to.angular_velocity.push_back(from.angular_velocity[k]);
  to.radius.push_back(from.radius[k]);
  to.density.push_back(from.density[k]);
  to.material.push_back(from.material[k]);
  to.group.push_back(from.group[k]);
}

} // namespace

ParticleExchange::ParticleExchange(const Scene& scene, ParticleSet& particles, double dt)
    : domain_(scene.domain) {
  double every = 0;
  auto consider = [&](double e) {
    if (e > 0) every = every > 0 ? std::min(every, e) : e;
  };
  // The pending tail holds the inlet groups' particles group after group, in scene order.
  const std::size_t first_pending = particles.size() - particles.pending;
  std::size_t k = first_pending;
  for (std::size_t g = 0; g < scene.groups.size(); ++g) {
    const GroupSpec& spec = scene.groups[g];
    if (spec.placement.kind != "inlet") continue;
    Inlet in;
    in.group = spec.name;
    in.placement = spec.placement;
    double total = 0;
    for (; k < particles.size() && particles.group[k] == static_cast<int>(g); ++k) {
      append_particle(in.queue, particles, k);
      total += sphere_mass(particles.density[k], particles.radius[k]);
      in.cumulative_mass.push_back(total);
    }
    consider(spec.placement.every);
    inlets_.push_back(std::move(in));
  }
  auto cut = [first_pending](auto& v) { v.resize(first_pending); };
  cut(particles.id), cut(particles.position), cut(particles.velocity), cut(particles.angular_velocity);
  cut(particles.radius), cut(particles.density), cut(particles.material), cut(particles.group);
  particles.pending = 0;
  for (const OutletSpec& o : scene.outlets) {
    outlets_.push_back(Outlet{o, 0, 0.0});
    consider(o.every);
  }
  every_steps_ =
      every > 0 ? std::max(1L, std::lround(every / dt)) : default_every_steps(scene.output.every, dt);
}

long ParticleExchange::default_every_steps(double output_every, double dt) {
  // Every frame falls on an exchange, so no frame shows a particle past an outlet: the largest divisor of
  // the frame interval up to 100 steps, unless that is so short that exchanges would cost more than steps.
  const long frame = output_every > 0 ? std::lround(output_every / dt) : 0;
  for (long e = std::min(100L, frame); e >= 20; --e)
    if (frame % e == 0) return e;
  return 100;
}

std::size_t ParticleExchange::waiting() const {
  std::size_t n = 0;
  for (const Inlet& in : inlets_)
    n += in.queue.size() - in.inserted;
  return n;
}

std::size_t ParticleExchange::owed(const Inlet& in, double time) const {
  const PlacementSpec& p = in.placement;
  const double open = time - p.start;
  if (open < 0) return 0;
  if (p.rate > 0)
    return std::min(in.queue.size(), static_cast<std::size_t>(std::floor(p.rate * open + 1e-9)));
  const double due = p.mass_rate * open * (1 + 1e-12);
  return static_cast<std::size_t>(
      std::upper_bound(in.cumulative_mass.begin(), in.cumulative_mass.end(), due) -
      in.cumulative_mass.begin());
}

ParticleSet ParticleExchange::place(Inlet& in, std::size_t target, const FrameData& frame, long step,
                                    std::size_t index) {
  ParticleSet out;
  const PlacementSpec& p = in.placement;
  double rmax = 0;
  for (std::size_t k = in.inserted; k < target; ++k)
    rmax = std::max(rmax, in.queue.radius[k]);
  double reach = rmax;
  for (double r : frame.radius)
    reach = std::max(reach, r);
  // The particles near the box (and those placed now) on a cell grid; periodic images included.
  HostCellGrid grid(domain_, 2 * reach);
  std::vector<Vec3d> near_x;
  std::vector<double> near_r;
  auto add_near = [&](const Vec3d& x, double r) {
    grid.insert(static_cast<int>(near_x.size()), x);
    near_x.push_back(x);
    near_r.push_back(r);
  };
  auto overlaps = [&](const Vec3d& x, double r) {
    return grid.any_neighbour(x, [&](int j) {
      const Vec3d d = grid.delta(x, near_x[j]);
      const double reach_ij = r + near_r[j];
      return d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < reach_ij * reach_ij;
    });
  };
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const double* x = &frame.position[3 * i];
    bool close = true;
    for (int a = 0; a < 3; ++a) // along a periodic axis an image across the seam may be near: keep all
      close = close && (domain_.periodic[a] || (x[a] > p.lo[a] - 2 * reach && x[a] < p.hi[a] + 2 * reach));
    if (close) add_near({x[0], x[1], x[2]}, frame.radius[i]);
  }
  Rng rng(p.seed, Rng::inlet, static_cast<std::uint64_t>(step) * 64 + index);
  for (std::size_t k = in.inserted; k < target; ++k) {
    const double r = in.queue.radius[k];
    bool placed = false;
    Vec3d x{};
    for (int t = 0; t < kTriesPerParticle && !placed; ++t) {
      for (int a = 0; a < 3; ++a) {
        const double lo = p.lo[a] + r, hi = p.hi[a] - r;
        x[a] = lo < hi ? rng.uniform(lo, hi) : 0.5 * (p.lo[a] + p.hi[a]);
      }
      placed = !overlaps(x, r);
    }
    if (!placed) {
      ++in.blocked;
      break; // the rest waits for the next exchange, in order
    }
    add_near(x, r);
    append_particle(out, in.queue, k);
    out.position.back() = x;
    in.mass += sphere_mass(in.queue.density[k], r);
    ++in.inserted;
  }
  return out;
}

void ParticleExchange::apply(Engine& engine) {
  const FrameData frame = engine.frame();
  std::vector<std::int64_t> gone;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const double* x = &frame.position[3 * i];
    for (Outlet& o : outlets_) {
      bool caught;
      if (o.spec.type == "plane") {
        double s = 0;
        for (int a = 0; a < 3; ++a)
          s += (x[a] - o.spec.point[a]) * o.spec.normal[a];
        caught = s < 0;
      } else {
        caught = true;
        for (int a = 0; a < 3; ++a)
          caught = caught && x[a] >= o.spec.lo[a] && x[a] <= o.spec.hi[a];
      }
      if (!caught) continue;
      gone.push_back(frame.id[i]);
      ++o.count;
      o.mass += frame.mass[i];
      break; // counted by the first outlet that holds it
    }
  }
  ParticleSet add;
  for (std::size_t n = 0; n < inlets_.size(); ++n) {
    Inlet& in = inlets_[n];
    const std::size_t target = owed(in, engine.time());
    if (target <= in.inserted) continue;
    const ParticleSet more = place(in, target, frame, engine.step(), n);
    for (std::size_t k = 0; k < more.size(); ++k)
      append_particle(add, more, k);
  }
  engine.exchange(gone, add);
}

void ParticleExchange::record(std::map<std::string, double>& columns, long particles) const {
  if (!active()) return;
  columns["particles"] = static_cast<double>(particles);
  for (const Inlet& in : inlets_) {
    columns["inlet_" + in.group + "_count"] = static_cast<double>(in.inserted);
    columns["inlet_" + in.group + "_mass"] = in.mass;
  }
  for (const Outlet& o : outlets_) {
    columns["outlet_" + o.spec.name + "_count"] = static_cast<double>(o.count);
    columns["outlet_" + o.spec.name + "_mass"] = o.mass;
  }
}

std::vector<std::string> ParticleExchange::shortfalls(double time) const {
  std::vector<std::string> out;
  for (const Inlet& in : inlets_) {
    const std::size_t due = owed(in, time);
    if (in.inserted >= due || in.blocked == 0) continue;
    char line[320];
    std::snprintf(
        line, sizeof line,
        "warning: inlet of group '%s' placed %zu of the %zu particles due by t = %.4g s: its box was "
        "full at %ld insertions; enlarge the box, lower the rate or give the particles a velocity "
        "away from it",
        in.group.c_str(), in.inserted, due, time, in.blocked);
    out.emplace_back(line);
  }
  return out;
}

void ParticleExchange::save(CheckpointData& c) const {
  for (const Inlet& in : inlets_) {
    c.scalars["inlet_" + in.group + "_inserted"] = static_cast<double>(in.inserted);
    c.scalars["inlet_" + in.group + "_mass"] = in.mass;
    c.scalars["inlet_" + in.group + "_blocked"] = static_cast<double>(in.blocked);
  }
  for (const Outlet& o : outlets_) {
    c.scalars["outlet_" + o.spec.name + "_count"] = static_cast<double>(o.count);
    c.scalars["outlet_" + o.spec.name + "_mass"] = o.mass;
  }
}

void ParticleExchange::load(const CheckpointData& c) {
  auto get = [&](const std::string& key) {
    const auto it = c.scalars.find(key);
    if (it == c.scalars.end())
      throw std::runtime_error("checkpoint lacks '" + key +
                               "' (written by a scene without this inlet/outlet)");
    return it->second;
  };
  for (Inlet& in : inlets_) {
    const double inserted = get("inlet_" + in.group + "_inserted");
    if (!(inserted >= 0 && inserted <= static_cast<double>(in.queue.size())))
      throw std::runtime_error("checkpoint's inlet count for group '" + in.group + "' is out of range");
    in.inserted = static_cast<std::size_t>(inserted);
    in.mass = get("inlet_" + in.group + "_mass");
    in.blocked = static_cast<long>(get("inlet_" + in.group + "_blocked"));
  }
  for (Outlet& o : outlets_) {
    o.count = static_cast<long>(get("outlet_" + o.spec.name + "_count"));
    o.mass = get("outlet_" + o.spec.name + "_mass");
  }
}

} // namespace cgdem
