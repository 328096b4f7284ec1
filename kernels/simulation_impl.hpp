#pragma once
// Out-of-line members of Simulation (host orchestration; the kernels live in their own headers).
#include <algorithm>
#include <cmath>
#include <string>

namespace cgdem::kernels {

template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::upload_particles() {
  const ParticleSet& ps = cfg_.particles;
  auto h_id = Kokkos::create_mirror_view(store_.id);
  auto h_x = Kokkos::create_mirror_view(store_.position);
  auto h_v = Kokkos::create_mirror_view(store_.velocity);
  auto h_w = Kokkos::create_mirror_view(store_.angular_velocity);
  auto h_r = Kokkos::create_mirror_view(store_.radius);
  auto h_m = Kokkos::create_mirror_view(store_.mass);
  auto h_I = Kokkos::create_mirror_view(store_.inertia);
  auto h_k = Kokkos::create_mirror_view(store_.scale_factor);
  auto h_mat = Kokkos::create_mirror_view(store_.material);
  auto h_g = Kokkos::create_mirror_view(store_.group);
  for (int i = 0; i < n_; ++i) {
    h_id(i) = ps.id[i];
    const Vec3 x = cfg_.domain.wrap(Vec3{ps.position[i][0], ps.position[i][1], ps.position[i][2]});
    for (int a = 0; a < 3; ++a) {
      h_x(i, a) = x[a];
      h_v(i, a) = ps.velocity[i][a];
      h_w(i, a) = ps.angular_velocity[i][a];
    }
    const double r = ps.radius[i];
    h_r(i) = r;
    h_m(i) = ps.density[i] * 4.0 / 3.0 * math::pi * r * r * r;
    h_I(i) = 0.4 * h_m(i) * r * r;
    h_k(i) = cfg_.scale_factor.empty() ? 1.0 : cfg_.scale_factor[i];
    h_mat(i) = ps.material[i];
    h_g(i) = ps.group[i];
  }
  Kokkos::deep_copy(store_.id, h_id);
  Kokkos::deep_copy(store_.position, h_x);
  Kokkos::deep_copy(store_.velocity, h_v);
  Kokkos::deep_copy(store_.angular_velocity, h_w);
  Kokkos::deep_copy(store_.radius, h_r);
  Kokkos::deep_copy(store_.mass, h_m);
  Kokkos::deep_copy(store_.inertia, h_I);
  Kokkos::deep_copy(store_.scale_factor, h_k);
  Kokkos::deep_copy(store_.material, h_mat);
  Kokkos::deep_copy(store_.group, h_g);
}

template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::upload_tables() {
  const int nm = cfg_.num_materials;
  pair_params_ = Kokkos::View<models::PairParameters**, Mem>("cgdem::kernels::pair_params", nm, nm);
  wall_params_ = Kokkos::View<models::PairParameters**, Mem>("cgdem::kernels::wall_params", nm, nm);
  auto hp = Kokkos::create_mirror_view(pair_params_);
  auto hw = Kokkos::create_mirror_view(wall_params_);
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nm; ++b) {
      hp(a, b) = cfg_.pair_params[a * nm + b];
      hw(a, b) = cfg_.wall_params[a * nm + b];
    }
  Kokkos::deep_copy(pair_params_, hp);
  Kokkos::deep_copy(wall_params_, hw);
  // Each wall part's place in a particle's wall-history row: H values, or a mesh part's slots.
  history_width_ = 0;
  for (Wall& w : cfg_.walls) {
    w.history_offset = history_width_;
    history_width_ += w.type == Wall::Mesh ? MeshSlots::width(H) : H;
  }
  meshes_.upload(cfg_.meshes, cfg_.walls);
  walls_ = Kokkos::View<Wall*, Mem>("cgdem::kernels::walls", cfg_.walls.size());
  upload_walls();
  placed_walls_ = Kokkos::View<PlacedWall*, Mem>("cgdem::kernels::placed_walls", cfg_.walls.size());
  placed_walls_host_ = Kokkos::create_mirror_view(placed_walls_);
}

template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::upload_walls() {
  auto hwalls = Kokkos::create_mirror_view(walls_);
  for (std::size_t w = 0; w < cfg_.walls.size(); ++w)
    hwalls(w) = cfg_.walls[w];
  Kokkos::deep_copy(walls_, hwalls);
}

template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::end_wall_segment(int wall, int segment, double time) {
  for (Wall& w : cfg_.walls) {
    if (w.owner != wall) continue;
    if (segment < 0)
      w.motion_stop = time;
    else if (segment < w.num_then)
      w.then_stop[segment] = time;
  }
  upload_walls();
}

template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::allocate_per_particle_scratch() {
  wall_history_ = HistoryView("cgdem::kernels::wall_history", n_, history_width_);
  const std::size_t scratch_bytes = reorder_scratch_bytes(std::size_t(history_width_) * sizeof(ForceReal));
  reorder_scratch_ =
      Kokkos::View<double*, Mem>("cgdem::kernels::reorder_scratch",
                                 std::size_t(n_) * ((scratch_bytes + sizeof(double) - 1) / sizeof(double)));
  identity_ = Kokkos::View<int*, Mem>("cgdem::kernels::identity", n_);
  old_index_ = Kokkos::View<int*, Mem>("cgdem::kernels::old_index", n_);
  auto id = identity_;
  Kokkos::parallel_for(
      "cgdem::kernels::iota", Kokkos::RangePolicy<ExecSpace>(0, n_), KOKKOS_LAMBDA(int i) { id(i) = i; });
  if (!cfg_.walls.empty())
    wall_force_record_ = Kokkos::View<Real* [3], Mem>("cgdem::kernels::wall_force_record",
                                                      2 * std::size_t(n_) * cfg_.walls.size());
}

template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::rebuild(bool first) {
  Kokkos::Timer timer;
  bins_.build(grid_, store_.position, n_);
  Kokkos::View<int*, Mem> old_index = identity_;
  const bool reorder = cfg_.reorder_every > 0 && builds_ % cfg_.reorder_every == 0;
  if (reorder) {
    // Keep the sort order as the map new index -> old index for the history transfer, then rebin in
    // the new order (cheap, and keeps binning and listing independent of whether we reordered).
    old_index = Kokkos::subview(bins_.order, std::make_pair(0, n_));
    Kokkos::deep_copy(ExecSpace(), old_index_, old_index);
    old_index = old_index_;
    Reorder<ExecSpace>::permute_store(store_, reorder_scratch_, old_index, n_);
    Reorder<ExecSpace>::permute(wall_history_, reorder_scratch_, old_index, n_);
    bins_.build(grid_, store_.position, n_);
  }
  Kokkos::fence();
  timers_.binning += timer.seconds();
  timer.reset();
  nl_.build(cfg_.domain, grid_, bins_, store_.position, store_.radius, cutoff_extra_, max_radius_, cfg_.reach,
            n_, old_index, !first);
  blocks_.build(cfg_.domain, grid_, bins_, n_);
  if (!meshes_.empty()) {
    meshes_.place(walls_, cfg_.walls, time_);
    meshes_.build(grid_, store_.position, store_.radius, n_, max_radius_, cutoff_extra_, time_);
  }
  displacement_since_build_ = 0;
  skip_displacement_ = 0;
  Kokkos::deep_copy(ExecSpace(), store_.position_at_build, store_.position);
  Kokkos::fence();
  timers_.neighbor_list += timer.seconds();
  ++builds_;
  ++timers_.list_builds;
}

template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::compute_forces(bool record_wall_forces, bool cleared) {
  Kokkos::Timer timer;
  Kokkos::View<Real* [3], Mem> record;
  if (record_wall_forces) record = wall_force_record_;
  // The walls where they are now, once per step rather than per particle (a few words each; on a
  // host backend the mirror is the view itself and the copy does nothing).
  for (std::size_t w = 0; w < cfg_.walls.size(); ++w)
    placed_walls_host_(w) = place(cfg_.walls[w], time_);
  Kokkos::deep_copy(placed_walls_, placed_walls_host_);
  if (!meshes_.empty()) meshes_.place(walls_, cfg_.walls, time_);
  using Forces = ContactForces<ExecSpace, Law>;
  typename Forces::Inputs in;
  in.domain = cfg_.domain;
  in.pair_params = pair_params_;
  in.wall_params = wall_params_;
  in.walls = placed_walls_;
  in.wall_history = wall_history_;
  in.wall_force = record;
  in.mesh = meshes_.geometry();
  in.dt = cfg_.dt;
  in.reach = cfg_.reach;
  in.max_radius = max_radius_;
  in.max_displacement = skip_displacement_;
  // On one thread the integrator's even split is the store in order: nothing to follow.
  const bool claims = Forces::compute(store_, nl_, blocks_, in, Law{}, n_, cleared, force_path_);
  blocks_.claims_recorded = claims && ExecSpace::concurrency() > 1;
  Kokkos::fence();
  timers_.forces += timer.seconds();
}

template <class Law, class ExecSpace>
Real Simulation<Law, ExecSpace>::max_overlap_fraction() {
  const auto p = store_;
  const auto offsets = nl_.offsets;
  const auto neigh = nl_.neighbors;
  const Domain domain = cfg_.domain;
  const auto walls = walls_;
  const int nwalls = static_cast<int>(walls_.extent(0));
  const Real t = time_;
  Real worst = 0;
  Kokkos::parallel_reduce(
      "cgdem::kernels::max_overlap", Kokkos::RangePolicy<ExecSpace>(0, n_),
      KOKKOS_LAMBDA(int i, Real& w) {
        const Vec3 xi = load3(p.position, i);
        const Real ri = p.radius(i);
        for (int s = offsets(i); s < offsets(i + 1); ++s) {
          const int j = neigh(s);
          const Real rj = p.radius(j);
          const Real ov = ri + rj - norm(domain.minimum_image(load3(p.position, j) - xi));
          const Real frac = ov / (ri < rj ? ri : rj);
          if (frac > w) w = frac;
        }
        for (int k = 0; k < nwalls; ++k) {
          const WallContact c = wall_contact(walls(k), t, xi, ri);
          if (c.reachable && c.overlap / ri > w) w = c.overlap / ri;
        }
        if (!math::isfinite(xi.x + xi.y + xi.z)) w = Kokkos::Experimental::infinity<Real>::value;
      },
      Kokkos::Max<Real>(worst));
  return worst;
}

template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::check_overlaps() {
  const Real worst = max_overlap_fraction();
  if (!(worst <= cfg_.max_overlap_fraction)) {
    char what[160];
    std::snprintf(what, sizeof what, "an overlap reached %.3g of the smaller radius (limit %.3g)", worst,
                  cfg_.max_overlap_fraction);
    throw BlowUpError(diagnose(what));
  }
  // An exploding pack need not overlap much at the moment of the check: particles flying apart faster
  // than half a radius per step can no longer resolve any contact.
  const auto p = store_;
  const Real dt = cfg_.dt;
  Real travel = 0;
  Kokkos::parallel_reduce(
      "cgdem::kernels::max_step_travel", Kokkos::RangePolicy<ExecSpace>(0, n_),
      KOKKOS_LAMBDA(int i, Real& w) {
        const Real t = norm(load3(p.velocity, i)) * dt / p.radius(i);
        if (t > w) w = t;
      },
      Kokkos::Max<Real>(travel));
  if (!(travel <= 0.5)) {
    char what[200];
    std::snprintf(
        what, sizeof what,
        "a particle moves %.3g of its radius per step (limit 0.5): contacts can no longer be resolved",
        travel);
    throw BlowUpError(diagnose(what));
  }
}

// Find the worst particle on the host and say what probably happened.
template <class Law, class ExecSpace>
std::string Simulation<Law, ExecSpace>::diagnose(const std::string& what) {
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), store_.position);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), store_.velocity);
  auto r = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), store_.radius);
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), store_.id);
  // Full neighbour sets on the host (the device list holds each pair once).
  auto half_off = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), nl_.offsets);
  auto half_nb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), nl_.neighbors);
  std::vector<std::vector<int>> partners(n_);
  for (int i = 0; i < n_; ++i)
    for (int s = half_off(i); s < half_off(i + 1); ++s) {
      partners[i].push_back(half_nb(s));
      partners[half_nb(s)].push_back(i);
    }
  std::vector<int> off(n_ + 1, 0), nb;
  for (int i = 0; i < n_; ++i) {
    nb.insert(nb.end(), partners[i].begin(), partners[i].end());
    off[i + 1] = static_cast<int>(nb.size());
  }
  int worst = -1;
  double worst_score = -1;
  std::string neighbours;
  for (int i = 0; i < n_; ++i) {
    const Vec3 xi{x(i, 0), x(i, 1), x(i, 2)};
    const Vec3 vi{v(i, 0), v(i, 1), v(i, 2)};
    double score = std::isfinite(norm2(xi) + norm2(vi)) ? 0 : 1e300;
    for (int s = off[i]; s < off[i + 1] && score < 1e300; ++s) {
      const int j = nb[s];
      const double ov = r(i) + r(j) - norm(cfg_.domain.minimum_image(Vec3{x(j, 0), x(j, 1), x(j, 2)} - xi));
      score = std::max(score, ov / std::min(r(i), r(j)));
    }
    score = std::max(score, norm(vi) * cfg_.dt / r(i)); // fast particles count as suspects too
    if (score > worst_score) {
      worst_score = score;
      worst = i;
    }
  }
  std::ostringstream msg;
  msg << "blow-up at step " << step_ << " (t = " << time_ << " s): " << what;
  if (worst >= 0) {
    msg << "; particle id " << id(worst) << " at (" << x(worst, 0) << ", " << x(worst, 1) << ", "
        << x(worst, 2) << ") velocity (" << v(worst, 0) << ", " << v(worst, 1) << ", " << v(worst, 2)
        << "), radius " << r(worst) << "; neighbours (id:overlap/radius)";
    int shown = 0;
    for (int s = off[worst]; s < off[worst + 1] && shown < 8; ++s, ++shown) {
      const int j = nb[s];
      const double ov = r(worst) + r(j) -
                        norm(cfg_.domain.minimum_image(Vec3{x(j, 0), x(j, 1), x(j, 2)} -
                                                       Vec3{x(worst, 0), x(worst, 1), x(worst, 2)}));
      msg << " " << id(j) << ":" << ov / std::min(r(worst), r(j));
    }
  }
  msg << "; likely cause: "
      << (step_ < 10
              ? "overlapping or too close initial particles, or a time step far above the stable limit"
              : "the time step (" + std::to_string(cfg_.dt) +
                    " s) is too large for the contact stiffness and impact speeds: use time.step: auto, "
                    "a smaller time.fraction, or run 'cgdem check' to see the estimate");
  msg << ". The last good frame is in the output file.";
  return msg.str();
}

template <class Law, class ExecSpace>
FrameData Simulation<Law, ExecSpace>::frame() {
  // Host copies in id order, so frames of one run line up row by row whatever the reorders did.
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), store_.id);
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), store_.position);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), store_.velocity);
  auto w = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), store_.angular_velocity);
  auto r = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), store_.radius);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), store_.mass);
  auto g = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), store_.group);
  std::vector<int> rank(n_);
  std::iota(rank.begin(), rank.end(), 0);
  std::sort(rank.begin(), rank.end(), [&](int a, int b) { return id(a) < id(b); });
  FrameData f;
  f.time = time_;
  f.step = step_;
  f.id.resize(n_);
  f.position.resize(3 * n_);
  f.velocity.resize(3 * n_);
  f.angular_velocity.resize(3 * n_);
  f.radius.resize(n_);
  f.mass.resize(n_);
  f.group.resize(n_);
  for (int k = 0; k < n_; ++k) {
    const int i = rank[k];
    f.id[k] = id(i);
    for (int a = 0; a < 3; ++a) {
      f.position[3 * k + a] = x(i, a);
      f.velocity[3 * k + a] = v(i, a);
      f.angular_velocity[3 * k + a] = w(i, a);
    }
    f.radius[k] = r(i);
    f.mass[k] = m(i);
    f.group[k] = g(i);
  }
  return f;
}

namespace detail {
template <class V>
std::vector<double> to_reals(const V& view) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view);
  std::vector<double> out(h.span());
  for (std::size_t k = 0; k < h.span(); ++k)
    out[k] = h.data()[k];
  return out;
}
template <class V>
std::vector<std::int64_t> to_ints(const V& view) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view);
  std::vector<std::int64_t> out(h.span());
  for (std::size_t k = 0; k < h.span(); ++k)
    out[k] = h.data()[k];
  return out;
}
template <class V, class T>
void from_vector(const V& view, const std::vector<T>& src, const char* name) {
  if (src.size() != view.span())
    throw std::runtime_error(std::string("checkpoint field '") + name + "' has " +
                             std::to_string(src.size()) + " values, expected " + std::to_string(view.span()));
  auto h = Kokkos::create_mirror_view(view);
  for (std::size_t k = 0; k < src.size(); ++k)
    h.data()[k] = static_cast<typename V::value_type>(src[k]);
  Kokkos::deep_copy(view, h);
}
} // namespace detail

// Everything the trajectory depends on, in the store's current order: particle fields, forces of the
// last evaluation (the next half kick uses them), the neighbour list with its history, wall history.
template <class Law, class ExecSpace>
CheckpointData Simulation<Law, ExecSpace>::checkpoint() {
  CheckpointData c;
  c.time = time_;
  c.step = step_;
  c.scalars["builds"] = static_cast<double>(builds_);
  c.scalars["num_slots"] = nl_.num_slots;
  c.scalars["history_size"] = H;
  c.scalars["mesh_built_at"] = meshes_.built_at();
  c.scalars["skip_displacement"] = skip_displacement_;
  ParticleStore<Mem>::for_each_field(store_, [&c](const char* name, const auto& field) {
    using T = typename std::decay_t<decltype(field)>::value_type;
    if constexpr (std::is_integral_v<T>)
      c.ints[name] = detail::to_ints(field);
    else
      c.reals[name] = detail::to_reals(field);
  });
  c.ints["nl_offsets"] = detail::to_ints(nl_.offsets);
  auto neigh = detail::to_ints(nl_.neighbors);
  neigh.resize(nl_.num_slots);
  c.ints["nl_neighbors"] = neigh;
  auto hist = detail::to_reals(nl_.history);
  hist.resize(std::size_t(nl_.num_slots) * H);
  c.reals["nl_history"] = hist;
  c.reals["wall_history"] = detail::to_reals(wall_history_);
  if (!cfg_.walls.empty()) c.reals["wall_force_record"] = detail::to_reals(wall_force_record_);
  return c;
}

template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::restore(const CheckpointData& c) {
  auto need = [&](const auto& map, const char* key) -> const auto& {
    auto it = map.find(key);
    if (it == map.end()) throw std::runtime_error(std::string("checkpoint lacks field '") + key + "'");
    return it->second;
  };
  const std::size_t count = need(c.ints, "id").size();
  if (count != std::size_t(n_)) {
    if (!cfg_.resizable)
      throw std::runtime_error("checkpoint holds " + std::to_string(count) + " particles but the scene has " +
                               std::to_string(n_));
    n_ = static_cast<int>(count);
    store_ = ParticleStore<Mem>(n_);
    allocate_per_particle_scratch();
  }
  if (static_cast<int>(need(c.scalars, "history_size")) != H)
    throw std::runtime_error("checkpoint was written by a different contact law (history size differs)");
  ParticleStore<Mem>::for_each_field(store_, [&](const char* name, const auto& field) {
    using T = typename std::decay_t<decltype(field)>::value_type;
    // Checkpoints of a single process written before the halo flag existed: every particle owned.
    if (std::string(name) == "halo" && c.ints.count(name) == 0)
      Kokkos::deep_copy(field, T(0));
    else if constexpr (std::is_integral_v<T>)
      detail::from_vector(field, need(c.ints, name), name);
    else
      detail::from_vector(field, need(c.reals, name), name);
  });
  max_radius_ = cfg_.max_radius;
  for (double r : need(c.reals, "radius"))
    max_radius_ = std::max<Real>(max_radius_, r);
  detail::from_vector(wall_history_, need(c.reals, "wall_history"), "wall_history");
  if (!cfg_.walls.empty()) {
    // Checkpoints written before the record held the moments too (3 values per particle and part, the
    // forces alone): their forces go into the force rows, the moments start at zero (they are the last
    // evaluation's, written to the series only, never integrated).
    const auto& record = need(c.reals, "wall_force_record");
    const std::size_t parts = cfg_.walls.size();
    if (record.size() == std::size_t(n_) * parts * 3 && record.size() * 2 == wall_force_record_.span()) {
      std::vector<double> both(2 * record.size(), 0.0);
      for (std::size_t e = 0; e < std::size_t(n_) * parts; ++e)
        for (int a = 0; a < 3; ++a)
          both[6 * e + a] = record[3 * e + a];
      detail::from_vector(wall_force_record_, both, "wall_force_record");
    } else {
      detail::from_vector(wall_force_record_, record, "wall_force_record");
    }
  }
  // The neighbour list exactly as it was: same slots, same order, same history.
  const auto& offs = need(c.ints, "nl_offsets");
  const auto& neigh = need(c.ints, "nl_neighbors");
  const auto& hist = need(c.reals, "nl_history");
  const int slots = static_cast<int>(neigh.size());
  nl_.offsets = Kokkos::View<int*, Mem>("cgdem::kernels::nl_offsets", n_ + 1);
  nl_.reserve(decltype(nl_)::capacity_for(slots));
  detail::from_vector(nl_.offsets, offs, "nl_offsets");
  {
    auto h = Kokkos::create_mirror_view(nl_.neighbors);
    for (int k = 0; k < slots; ++k)
      h(k) = static_cast<int>(neigh[k]);
    Kokkos::deep_copy(nl_.neighbors, h);
    auto hh = Kokkos::create_mirror_view(nl_.history);
    for (std::size_t k = 0; k < hist.size(); ++k)
      hh.data()[k] = hist[k];
    Kokkos::deep_copy(nl_.history, hh);
  }
  nl_.num_slots = slots;
  nl_.compute_gaps(cfg_.domain, store_.position_at_build, store_.radius, cfg_.reach, n_);
  // Unknown until the next kick_drift measures it: skip nothing on a force pass before that.
  displacement_since_build_ = Kokkos::Experimental::infinity<Real>::value;
  // The force pass's skipping goes on from the largest displacement the run had seen since its build (a
  // checkpoint without it, one gathered over MPI ranks or older: skip nothing until the next build).
  const auto skip = c.scalars.find("skip_displacement");
  skip_displacement_ = skip != c.scalars.end() ? skip->second : Kokkos::Experimental::infinity<Real>::value;
  // The force pass's blocks from the cells the list was built with (positions at the build).
  bins_.build(grid_, store_.position_at_build, n_);
  blocks_.build(cfg_.domain, grid_, bins_, n_);
  nl_.partner_slots_indexed = false; // the slots were replaced
  if (!meshes_.empty()) {
    // The mesh candidates as the last build made them: vertices and particles where they were then.
    const Real built_at = need(c.scalars, "mesh_built_at");
    meshes_.place(walls_, cfg_.walls, built_at);
    meshes_.build(grid_, store_.position_at_build, store_.radius, n_, max_radius_, cutoff_extra_, built_at);
  }
  builds_ = static_cast<long>(need(c.scalars, "builds"));
  step_ = c.step;
  time_ = c.time;
}

// Host-side edit of the full state, then the ordinary restore and a list build: removed particles leave
// with their pair and wall history, kept particles keep theirs (the compacted list carries it into the
// build), and added particles join the list at the build. Costs a state round trip through the host, so
// drivers call it every few hundred steps, not every step.
template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::exchange(const std::vector<std::int64_t>& remove_ids,
                                          const ParticleSet& add) {
  if (remove_ids.empty() && add.size() == 0) return;
  CheckpointData c = checkpoint();
  const std::vector<std::int64_t> ids = c.ints.at("id");
  const std::size_t n_old = ids.size(), parts = cfg_.walls.size();
  std::vector<std::int64_t> gone(remove_ids);
  std::sort(gone.begin(), gone.end());
  std::vector<int> new_index(n_old, -1);
  int kept = 0;
  for (std::size_t i = 0; i < n_old; ++i)
    if (!std::binary_search(gone.begin(), gone.end(), ids[i])) new_index[i] = kept++;
  const std::size_t n_new = std::size_t(kept) + add.size();
  // Rows of `width` values per particle: keep the kept ones' rows in order, append zero rows.
  auto compact = [&](auto& values, std::size_t width) {
    using T = typename std::decay_t<decltype(values)>::value_type;
    std::vector<T> out;
    out.reserve(n_new * width);
    for (std::size_t i = 0; i < n_old; ++i)
      if (new_index[i] >= 0)
        out.insert(out.end(), values.begin() + i * width, values.begin() + (i + 1) * width);
    out.resize(n_new * width, T(0));
    values = std::move(out);
  };
  ParticleStore<Mem>::for_each_field(store_, [&](const char* name, const auto& field) {
    using FieldView = std::decay_t<decltype(field)>;
    constexpr std::size_t width = ParticleStore<Mem>::template columns<FieldView>();
    if constexpr (std::is_integral_v<typename FieldView::value_type>)
      compact(c.ints.at(name), width);
    else
      compact(c.reals.at(name), width);
  });
  compact(c.reals.at("wall_history"), std::size_t(history_width_));
  if (parts > 0) compact(c.reals.at("wall_force_record"), parts * 6);
  // The added particles' own fields.
  for (std::size_t k = 0; k < add.size(); ++k) {
    const std::size_t i = std::size_t(kept) + k;
    const int g = add.group[k];
    const double r = add.radius[k], m = add.density[k] * 4.0 / 3.0 * math::pi * r * r * r;
    const Vec3 x = cfg_.domain.wrap(Vec3{add.position[k][0], add.position[k][1], add.position[k][2]});
    c.ints["id"][i] = add.id[k];
    c.ints["material"][i] = cfg_.group_slot.at(std::size_t(g));
    c.ints["group"][i] = g;
    for (int a = 0; a < 3; ++a) {
      c.reals["position"][3 * i + a] = x[a];
      c.reals["position_at_build"][3 * i + a] = x[a];
      c.reals["velocity"][3 * i + a] = add.velocity[k][a];
      c.reals["angular_velocity"][3 * i + a] = add.angular_velocity[k][a];
    }
    c.reals["radius"][i] = r;
    c.reals["mass"][i] = m;
    c.reals["inertia"][i] = 0.4 * m * r * r;
    c.reals["scale_factor"][i] = cfg_.group_scale.at(std::size_t(g));
  }
  // The neighbour list without the removed particles (partners renumbered, order kept: a pair stays under
  // its lower index); the added particles have no slots until the build below.
  const std::vector<std::int64_t> offs = c.ints.at("nl_offsets"), neigh = c.ints.at("nl_neighbors");
  const std::vector<double> hist = c.reals.at("nl_history");
  std::vector<std::int64_t> new_offs{0}, new_neigh;
  std::vector<double> new_hist;
  for (std::size_t i = 0; i < n_old; ++i) {
    if (new_index[i] < 0) continue;
    for (auto s = offs[i]; s < offs[i + 1]; ++s) {
      const int j = new_index[std::size_t(neigh[std::size_t(s)])];
      if (j < 0) continue;
      new_neigh.push_back(j);
      new_hist.insert(new_hist.end(), hist.begin() + s * H, hist.begin() + (s + 1) * H);
    }
    new_offs.push_back(static_cast<std::int64_t>(new_neigh.size()));
  }
  new_offs.resize(n_new + 1, new_offs.back());
  c.ints["nl_offsets"] = std::move(new_offs);
  c.ints["nl_neighbors"] = std::move(new_neigh);
  c.reals["nl_history"] = std::move(new_hist);
  const bool resizable = cfg_.resizable;
  cfg_.resizable = true;
  restore(c);
  cfg_.resizable = resizable;
  rebuild(false);
}

} // namespace cgdem::kernels

namespace cgdem::kernels {

// The index and row buffers are kept between calls (a halo refresh runs every step) and grow only.
template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::stage_state_rows(const std::vector<int>& index) {
  const std::size_t count = index.size();
  if (row_index_.extent(0) < count) {
    row_index_ = Kokkos::View<int*, Mem>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "cgdem::kernels::row_index"), count);
    row_buffer_ = Kokkos::View<double**, Kokkos::LayoutRight, Mem>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "cgdem::kernels::row_buffer"), count, kStateRowWidth);
  }
  Kokkos::View<const int*, Kokkos::HostSpace, Kokkos::MemoryUnmanaged> h_index(index.data(), count);
  Kokkos::deep_copy(Kokkos::subview(row_index_, std::make_pair(std::size_t(0), count)), h_index);
}

template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::read_state_rows(const std::vector<int>& index, std::vector<double>& rows) {
  constexpr int W = kStateRowWidth;
  const int count = static_cast<int>(index.size());
  rows.resize(std::size_t(count) * W);
  if (count == 0) return;
  stage_state_rows(index);
  const auto d_index = row_index_;
  const auto d_rows = row_buffer_;
  const ParticleStore<Mem> p = store_;
  Kokkos::parallel_for(
      "cgdem::read_state_rows", Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(int k) {
        const int i = d_index(k);
        for (int a = 0; a < 3; ++a) {
          d_rows(k, a) = p.position(i, a);
          d_rows(k, 3 + a) = p.velocity(i, a);
          d_rows(k, 6 + a) = p.angular_velocity(i, a);
          d_rows(k, 9 + a) = p.force(i, a);
          d_rows(k, 12 + a) = p.torque(i, a);
        }
      });
  Kokkos::View<double**, Kokkos::LayoutRight, Kokkos::HostSpace, Kokkos::MemoryUnmanaged> h_rows(rows.data(),
                                                                                                 count, W);
  Kokkos::deep_copy(h_rows, Kokkos::subview(d_rows, std::make_pair(0, count), Kokkos::ALL));
}

template <class Law, class ExecSpace>
void Simulation<Law, ExecSpace>::write_state_rows(const std::vector<int>& index,
                                                  const std::vector<double>& rows) {
  constexpr int W = kStateRowWidth;
  const int count = static_cast<int>(index.size());
  if (rows.size() != std::size_t(count) * W)
    throw std::invalid_argument("write_state_rows: " + std::to_string(rows.size()) + " values for " +
                                std::to_string(count) + " particles");
  if (count == 0) return;
  stage_state_rows(index);
  Kokkos::View<const double**, Kokkos::LayoutRight, Kokkos::HostSpace, Kokkos::MemoryUnmanaged> h_rows(
      rows.data(), count, W);
  Kokkos::deep_copy(Kokkos::subview(row_buffer_, std::make_pair(0, count), Kokkos::ALL), h_rows);
  const auto d_index = row_index_;
  const auto d_rows = row_buffer_;
  const ParticleStore<Mem> p = store_;
  Kokkos::parallel_for(
      "cgdem::write_state_rows", Kokkos::RangePolicy<ExecSpace>(0, count), KOKKOS_LAMBDA(int k) {
        const int i = d_index(k);
        for (int a = 0; a < 3; ++a) {
          p.position(i, a) = d_rows(k, a);
          p.velocity(i, a) = d_rows(k, 3 + a);
          p.angular_velocity(i, a) = d_rows(k, 6 + a);
          p.force(i, a) = d_rows(k, 9 + a);
          p.torque(i, a) = d_rows(k, 12 + a);
        }
      });
  Kokkos::fence();
}

template <class Law, class ExecSpace>
std::vector<std::int64_t> Simulation<Law, ExecSpace>::store_ids() {
  return detail::to_ints(store_.id);
}

} // namespace cgdem::kernels
