#include "parallel/distributed_engine.hpp"

#include <stdexcept>

#ifndef CGDEM_HAVE_MPI

namespace cgdem::parallel {
std::unique_ptr<Engine> make_distributed_engine(std::unique_ptr<Engine>, const Domain&, double) {
  throw std::runtime_error("this cgdem was built without MPI (configure with -DCGDEM_MPI=ON and Open MPI)");
}
} // namespace cgdem::parallel

#else

#include <mpi.h>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <string>
#include <utility>
#include <vector>
#include "parallel/decomposition.hpp"

namespace cgdem::parallel {

namespace {

bool per_pair(const std::string& name) {
  return name == "nl_history" || name == "nl_offsets" || name == "nl_neighbors";
}

// A checkpoint's per-particle arrays laid out as one row of doubles per particle (integers are ids,
// indices and flags: exact in a double).
struct RowLayout {
  struct Field {
    std::string name;
    bool integer;
    std::size_t width, offset;
  };
  std::vector<Field> fields;
  std::size_t width = 0, id_at = 0, position_at = 0;

  static RowLayout of(const CheckpointData& c) {
    RowLayout l;
    const std::size_t n = c.ints.at("id").size();
    if (n == 0) throw std::logic_error("row layout of an empty checkpoint");
    auto add = [&](const std::string& name, std::size_t size, bool integer) {
      if (per_pair(name)) return;
      if (size % n) throw std::logic_error("checkpoint array '" + name + "' is not per particle");
      l.fields.push_back({name, integer, size / n, l.width});
      if (name == "id") l.id_at = l.width;
      if (name == "position") l.position_at = l.width;
      l.width += size / n;
    };
    for (const auto& [name, v] : c.reals)
      add(name, v.size(), false);
    for (const auto& [name, v] : c.ints)
      add(name, v.size(), true);
    return l;
  }

  // A checkpoint's arrays in layout order, looked up once (absent ones, as the halo flag in a checkpoint
  // written before it existed, read as zeros).
  struct Source {
    std::vector<const double*> reals;
    std::vector<const std::int64_t*> ints;
  };
  Source source(const CheckpointData& c) const {
    Source src;
    for (const Field& f : fields) {
      if (f.integer) {
        auto it = c.ints.find(f.name);
        src.ints.push_back(it == c.ints.end() ? nullptr : it->second.data());
        src.reals.push_back(nullptr);
      } else {
        auto it = c.reals.find(f.name);
        src.reals.push_back(it == c.reals.end() ? nullptr : it->second.data());
        src.ints.push_back(nullptr);
      }
    }
    return src;
  }

  // Appends particle i's row.
  void append_row(const Source& src, std::size_t i, std::vector<double>& out) const {
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const Field& f = fields[k];
      const std::size_t at = i * f.width;
      if (f.integer) {
        for (std::size_t w = 0; w < f.width; ++w)
          out.push_back(src.ints[k] ? static_cast<double>(src.ints[k][at + w]) : 0.0);
      } else {
        for (std::size_t w = 0; w < f.width; ++w)
          out.push_back(src.reals[k] ? src.reals[k][at + w] : 0.0);
      }
    }
  }
};

// Each pair's history as a record: lower id, higher id, then H values seen from the lower-id particle.
struct PairRecords {
  int history = 0;
  std::size_t width() const { return 2 + std::size_t(history); }
};

template <class T>
std::vector<T> concat(const std::vector<std::vector<T>>& parts, std::vector<int>& counts) {
  std::vector<T> out;
  counts.clear();
  for (const auto& p : parts) {
    counts.push_back(static_cast<int>(p.size()));
    out.insert(out.end(), p.begin(), p.end());
  }
  return out;
}

std::vector<int> displacements(const std::vector<int>& counts) {
  std::vector<int> d(counts.size(), 0);
  for (std::size_t r = 1; r < counts.size(); ++r)
    d[r] = d[r - 1] + counts[r - 1];
  return d;
}

// Every rank sends parts[r] to rank r and gets back what each rank sent it, concatenated in rank order.
std::vector<double> all_to_all(const std::vector<std::vector<double>>& parts, MPI_Comm comm) {
  std::vector<int> send_counts;
  const std::vector<double> send = concat(parts, send_counts);
  std::vector<int> recv_counts(parts.size());
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm);
  const std::vector<int> sd = displacements(send_counts), rd = displacements(recv_counts);
  std::vector<double> recv(std::size_t(rd.back() + recv_counts.back()));
  MPI_Alltoallv(send.data(), send_counts.data(), sd.data(), MPI_DOUBLE, recv.data(), recv_counts.data(),
                rd.data(), MPI_DOUBLE, comm);
  return recv;
}

std::vector<double> all_gather(const std::vector<double>& mine, MPI_Comm comm) {
  int size = 0;
  MPI_Comm_size(comm, &size);
  int count = static_cast<int>(mine.size());
  std::vector<int> counts(size);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  const std::vector<int> d = displacements(counts);
  std::vector<double> all(std::size_t(d.back() + counts.back()));
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), d.data(), MPI_DOUBLE, comm);
  return all;
}

class DistributedEngine final : public Engine {
public:
  DistributedEngine(std::unique_ptr<Engine> whole, const Domain& domain, double skin)
      : local_(std::move(whole)), domain_(domain), skin_(skin) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
    // From the engine holding every particle, so every rank has the same width: twice the largest radius,
    // the interaction range and the skin, plus half a skin for the step on which a particle first moves
    // more than half a skin (the redistribution follows that step).
    halo_width_ = local_->interaction_cutoff() + 0.5 * skin;
    const CheckpointData c = local_->checkpoint();
    layout_ = RowLayout::of(c);
    pairs_.history = static_cast<int>(c.scalars.at("history_size"));
    restore(c);
  }

  // The ranks redistribute (and every rank rebuilds its list) once some particle anywhere has moved this
  // much of the skin: a little before a rank's own engine would rebuild at half a skin, so that the build
  // happens once, after the redistribution, rather than once before it and once after. A particle faster
  // than 0.05 skin per step makes its rank rebuild on its own first, which only costs the second build.
  static constexpr double kRedistributeAt = 0.45;

  void advance(long steps) override {
    for (long s = 0; s < steps; ++s) {
      refresh_halo();
      const long builds = local_->timers().list_builds;
      int status = 0; // 0: nothing to do, 1: a list was rebuilt (redistribute), 2: blow-up, 3: other error
      std::string what;
      try {
        local_->advance(1);
        if (local_->timers().list_builds != builds ||
            local_->displacement_since_build() > kRedistributeAt * skin_)
          status = 1;
      } catch (const BlowUpError& e) {
        status = 2;
        what = e.what();
      } catch (const std::exception& e) {
        status = 3;
        what = e.what();
      }
      // The time a rank waits here for the slowest one is counted as communication.
      const double start = MPI_Wtime();
      int any = 0;
      MPI_Allreduce(&status, &any, 1, MPI_INT, MPI_MAX, comm_);
      communication_seconds_ += MPI_Wtime() - start;
      if (any >= 2) {
        // Every rank throws the diagnosis of the lowest failing rank, so rank 0 can print it.
        int failing = status >= 2 ? rank_ : size_;
        MPI_Allreduce(MPI_IN_PLACE, &failing, 1, MPI_INT, MPI_MIN, comm_);
        int length = static_cast<int>(what.size());
        MPI_Bcast(&length, 1, MPI_INT, failing, comm_);
        what.resize(std::size_t(length));
        MPI_Bcast(what.data(), length, MPI_CHAR, failing, comm_);
        what = "rank " + std::to_string(failing) + ": " + what;
        if (any == 2) throw BlowUpError(what);
        throw std::runtime_error(what);
      }
      if (any == 1) redistribute();
    }
  }

  Observables observe() override {
    Observables o = local_->observe();
    double sums[8] = {
        o.kinetic_energy, o.rotational_energy, o.momentum[0], o.momentum[1], o.momentum[2], 0, 0, 0};
    long counts[2] = {o.contacts - o.pair_contact_ends / 2, o.pair_contact_ends};
    double maxima[2] = {o.max_speed, o.max_overlap_fraction};
    MPI_Allreduce(MPI_IN_PLACE, sums, 5, MPI_DOUBLE, MPI_SUM, comm_);
    MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_LONG, MPI_SUM, comm_);
    MPI_Allreduce(MPI_IN_PLACE, maxima, 2, MPI_DOUBLE, MPI_MAX, comm_);
    o.kinetic_energy = sums[0];
    o.rotational_energy = sums[1];
    for (int a = 0; a < 3; ++a)
      o.momentum[a] = sums[2 + a];
    o.contacts = counts[0] + counts[1] / 2;
    o.pair_contact_ends = counts[1];
    o.max_speed = maxima[0];
    o.max_overlap_fraction = maxima[1];
    for (auto* loads : {&o.wall_force, &o.wall_torque})
      if (!loads->empty())
        MPI_Allreduce(MPI_IN_PLACE, loads->data(), static_cast<int>(loads->size()), MPI_DOUBLE, MPI_SUM,
                      comm_);
    return o;
  }

  void rebuild_neighbors() override { redistribute(); }

  FrameData frame() override {
    const CheckpointData c = gather();
    FrameData f;
    f.time = c.time;
    f.step = c.step;
    f.id = c.ints.at("id");
    f.position = c.reals.at("position");
    f.velocity = c.reals.at("velocity");
    f.angular_velocity = c.reals.at("angular_velocity");
    f.radius = c.reals.at("radius");
    f.mass = c.reals.at("mass");
    const auto& g = c.ints.at("group");
    f.group.assign(g.begin(), g.end());
    return f;
  }

  CheckpointData checkpoint() override { return gather(); }

  // Every rank is given the same whole state (each reads the checkpoint file, or the engine holding every
  // particle at the start) and keeps its brick's share: no communication.
  void restore(const CheckpointData& whole) override {
    const std::size_t n = whole.ints.at("id").size();
    const std::vector<double>& x = whole.reals.at("position");
    if (whole.scalars.count("history_size") &&
        static_cast<int>(whole.scalars.at("history_size")) != pairs_.history)
      throw std::runtime_error("checkpoint was written by a different contact law (history size differs)");
    decomposition_ = Decomposition::make(domain_, x, size_, halo_width_);
    std::vector<char> keep(n, 0);
    std::vector<double> rows;
    const RowLayout::Source from = layout_.source(whole);
    for (std::size_t i = 0; i < n; ++i)
      if (decomposition_.near(&x[3 * i], rank_)) {
        keep[i] = 1;
        layout_.append_row(from, i, rows);
      }
    const std::vector<double> records =
        records_of(whole, [&](std::size_t i, std::size_t j) { return keep[i] && keep[j]; });
    install(assemble(rows, records, rank_, whole));
  }

  void exchange(const std::vector<std::int64_t>&, const ParticleSet&) override {
    throw std::runtime_error("inlets and outlets run in one process: run this scene without mpirun");
  }
  void read_state_rows(const std::vector<int>&, std::vector<double>&) override {
    throw std::logic_error("state rows of a distributed engine: ask its rank's engine");
  }
  void write_state_rows(const std::vector<int>&, const std::vector<double>&) override {
    throw std::logic_error("state rows of a distributed engine: ask its rank's engine");
  }
  void end_wall_segment(int wall, int segment, double time) override {
    local_->end_wall_segment(wall, segment, time); // every rank decides alike from the reduced wall force
  }
  std::vector<std::int64_t> store_ids() override { return local_->store_ids(); }
  void flip_pair_history(double* h) const override { local_->flip_pair_history(h); }
  double interaction_cutoff() const override { return local_->interaction_cutoff(); }
  double displacement_since_build() const override { return local_->displacement_since_build(); }
  double time() const override { return local_->time(); }
  long step() const override { return local_->step(); }
  int size() const override { return owned_total_; }
  // Rank 0's timers, but the communication of the rank that spent the most in it: a rank waiting for a
  // slower one (more particles, or a slower core) shows the imbalance there.
  StepTimers timers() const override {
    StepTimers t = local_->timers();
    MPI_Allreduce(&communication_seconds_, &t.communication, 1, MPI_DOUBLE, MPI_MAX, comm_);
    t.load_imbalance = load_imbalance_;
    t.rebalances = rebalances_;
    return t;
  }
  std::size_t bytes() const override { return local_->bytes(); }
  std::string physics() const override { return local_->physics(); }
  std::string backend() const override {
    return local_->backend() + " x " + std::to_string(size_) + " MPI ranks (" + decomposition_.describe() +
           ")";
  }

private:
  // The records of the list's pairs with a history, filtered by include(i, j) on store indices.
  template <class Include>
  std::vector<double> records_of(const CheckpointData& c, Include&& include) const {
    const auto& id = c.ints.at("id");
    const auto& offs = c.ints.at("nl_offsets");
    const auto& neigh = c.ints.at("nl_neighbors");
    const auto& hist = c.reals.at("nl_history");
    const int H = pairs_.history;
    std::vector<double> out, h(std::size_t(std::max(H, 1)));
    for (std::size_t i = 0; i + 1 < offs.size(); ++i)
      for (auto s = offs[i]; s < offs[i + 1]; ++s) {
        const std::size_t j = std::size_t(neigh[std::size_t(s)]);
        bool any = false;
        for (int k = 0; k < H; ++k) {
          h[k] = hist[std::size_t(s) * H + k];
          any = any || h[k] != 0;
        }
        if (!any || !include(i, j)) continue; // the list carries only histories across a build
        std::int64_t a = id[i], b = id[j];
        if (a > b) {
          std::swap(a, b);
          local_->flip_pair_history(h.data());
        }
        out.push_back(static_cast<double>(a));
        out.push_back(static_cast<double>(b));
        out.insert(out.end(), h.begin(), h.begin() + H);
      }
    return out;
  }

  // A checkpoint of the given rows (any order) and pair records, in id order; `owner` >= 0 marks the
  // particles outside its brick as halo copies, -1 keeps all as owned (the gathered whole state).
  CheckpointData assemble(const std::vector<double>& rows, const std::vector<double>& records, int owner,
                          const CheckpointData& like) const {
    const std::size_t W = layout_.width, n = rows.size() / W;
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return rows[a * W + layout_.id_at] < rows[b * W + layout_.id_at];
    });
    CheckpointData c;
    c.time = like.time;
    c.step = like.step;
    for (const char* key : {"builds", "mesh_built_at", "history_size"})
      if (like.scalars.count(key)) c.scalars[key] = like.scalars.at(key);
    c.scalars["history_size"] = pairs_.history;
    std::vector<std::int64_t> ids(n);
    for (std::size_t k = 0; k < n; ++k)
      ids[k] = static_cast<std::int64_t>(rows[order[k] * W + layout_.id_at]);
    for (const auto& f : layout_.fields) {
      if (f.integer) {
        auto& v = c.ints[f.name];
        v.resize(n * f.width);
        for (std::size_t k = 0; k < n; ++k)
          for (std::size_t w = 0; w < f.width; ++w)
            v[k * f.width + w] = static_cast<std::int64_t>(rows[order[k] * W + f.offset + w]);
      } else {
        auto& v = c.reals[f.name];
        v.resize(n * f.width);
        for (std::size_t k = 0; k < n; ++k)
          for (std::size_t w = 0; w < f.width; ++w)
            v[k * f.width + w] = rows[order[k] * W + f.offset + w];
      }
    }
    const std::vector<double>& position = c.reals["position"];
    auto& halo = c.ints["halo"];
    halo.assign(n, 0);
    if (owner >= 0)
      for (std::size_t k = 0; k < n; ++k)
        halo[k] = decomposition_.rank_of(&position[3 * k]) != owner;
    // The pairs whose two particles are both here, under the lower index (the lower id: rows are in id
    // order), partners ascending.
    const std::size_t RW = pairs_.width();
    std::vector<std::pair<std::pair<std::size_t, std::size_t>, std::size_t>> slots;
    for (std::size_t r = 0; r < records.size() / RW; ++r) {
      const auto a = static_cast<std::int64_t>(records[r * RW]),
                 b = static_cast<std::int64_t>(records[r * RW + 1]);
      const auto ia = std::lower_bound(ids.begin(), ids.end(), a),
                 ib = std::lower_bound(ids.begin(), ids.end(), b);
      if (ia == ids.end() || *ia != a || ib == ids.end() || *ib != b) continue;
      slots.push_back({{std::size_t(ia - ids.begin()), std::size_t(ib - ids.begin())}, r});
    }
    std::sort(slots.begin(), slots.end());
    auto& offs = c.ints["nl_offsets"];
    auto& neigh = c.ints["nl_neighbors"];
    auto& hist = c.reals["nl_history"];
    offs.assign(n + 1, 0);
    for (const auto& s : slots) {
      ++offs[s.first.first + 1];
      neigh.push_back(static_cast<std::int64_t>(s.first.second));
      hist.insert(hist.end(), records.begin() + s.second * RW + 2, records.begin() + (s.second + 1) * RW);
    }
    for (std::size_t i = 0; i < n; ++i)
      offs[i + 1] += offs[i];
    c.scalars["num_slots"] = static_cast<double>(slots.size());
    return c;
  }

  // The local engine takes its share; the halo exchange plan follows from where each particle is.
  void install(const CheckpointData& c) {
    local_->restore(c);
    local_->rebuild_neighbors();
    make_plan();
  }

  // Each particle to the ranks it is near (its new owner among them), each pair's history with the pair's
  // lower-id particle, from the rank owning that particle.
  void redistribute() {
    const double start = MPI_Wtime();
    const CheckpointData c = local_->checkpoint();
    const auto& halo = c.ints.at("halo");
    const auto& x = c.reals.at("position");
    const auto& id = c.ints.at("id");
    const std::size_t n = id.size();
    rebalance_if_needed(halo, x);
    const RowLayout::Source from = layout_.source(c);
    std::vector<std::vector<double>> rows(size_), records(size_);
    std::vector<std::vector<int>> dest(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (halo[i]) continue;
      for (int r = 0; r < size_; ++r)
        if (decomposition_.near(&x[3 * i], r)) {
          dest[i].push_back(r);
          layout_.append_row(from, i, rows[r]);
        }
    }
    const std::size_t RW = pairs_.width();
    const std::vector<double> mine = records_of(c, [&](std::size_t i, std::size_t j) {
      const std::size_t lower = id[i] < id[j] ? i : j;
      return halo[lower] == 0;
    });
    // Each record goes where its lower-id particle goes (owned here).
    std::unordered_map<std::int64_t, std::size_t> index_of;
    for (std::size_t i = 0; i < n; ++i)
      if (!halo[i]) index_of.emplace(id[i], i);
    for (std::size_t r = 0; r < mine.size() / RW; ++r) {
      const std::size_t i = index_of.at(static_cast<std::int64_t>(mine[r * RW]));
      for (int to : dest[i])
        records[to].insert(records[to].end(), mine.begin() + r * RW, mine.begin() + (r + 1) * RW);
    }
    const std::vector<double> my_rows = all_to_all(rows, comm_);
    const std::vector<double> my_records = all_to_all(records, comm_);
    const CheckpointData mine_now = assemble(my_rows, my_records, rank_, c);
    communication_seconds_ += MPI_Wtime() - start;
    install(mine_now);
  }

  // The owned particles and the histories of their pairs (lower-id particle owned here) from all ranks:
  // the single-process state, on every rank.
  CheckpointData gather() {
    const CheckpointData c = local_->checkpoint();
    const auto& halo = c.ints.at("halo");
    const auto& id = c.ints.at("id");
    std::vector<double> rows;
    const RowLayout::Source from = layout_.source(c);
    for (std::size_t i = 0; i < halo.size(); ++i)
      if (!halo[i]) layout_.append_row(from, i, rows);
    const std::vector<double> mine =
        records_of(c, [&](std::size_t i, std::size_t j) { return halo[id[i] < id[j] ? i : j] == 0; });
    return assemble(all_gather(rows, comm_), all_gather(mine, comm_), -1, c);
  }

  // When the ranks' particle counts have drifted more than kRebalanceAbove apart (a pile collapsing, a
  // mixer throwing its particles outwards), new cuts at the quantiles of the particles' positions now; the
  // redistribution that follows moves the particles to their new bricks with their history as always.
  static constexpr double kRebalanceAbove = 0.10;
  void rebalance_if_needed(const std::vector<std::int64_t>& halo, const std::vector<double>& x) {
    long owned[2] = {0, 0};
    for (auto h : halo)
      owned[0] += h == 0;
    owned[1] = owned[0];
    MPI_Allreduce(MPI_IN_PLACE, &owned[0], 1, MPI_LONG, MPI_MAX, comm_);
    MPI_Allreduce(MPI_IN_PLACE, &owned[1], 1, MPI_LONG, MPI_SUM, comm_);
    const double mean = double(owned[1]) / size_;
    if (mean <= 0 || owned[0] / mean - 1 <= kRebalanceAbove) return;
    std::vector<double> mine;
    for (std::size_t i = 0; i < halo.size(); ++i)
      if (!halo[i]) mine.insert(mine.end(), x.begin() + 3 * i, x.begin() + 3 * i + 3);
    decomposition_ = Decomposition::make(domain_, all_gather(mine, comm_), size_, halo_width_);
    ++rebalances_;
  }

  // Who sends which particles' state to whom before each step: the owner to every rank it is near,
  // in id order on both sides.
  void make_plan() {
    const std::vector<std::int64_t> ids = local_->store_ids();
    const int n = static_cast<int>(ids.size());
    std::vector<int> all(n);
    std::iota(all.begin(), all.end(), 0);
    std::vector<double> state;
    local_->read_state_rows(all, state); // the positions lead each row
    std::vector<std::vector<std::pair<std::int64_t, int>>> send(size_), recv(size_);
    int owned = 0;
    for (int i = 0; i < n; ++i) {
      const double* x = &state[std::size_t(i) * kStateRowWidth];
      const int owner = decomposition_.rank_of(x);
      if (owner != rank_) {
        recv[owner].push_back({ids[i], i});
        continue;
      }
      ++owned;
      for (int r = 0; r < size_; ++r)
        if (r != rank_ && decomposition_.near(x, r)) send[r].push_back({ids[i], i});
    }
    send_index_.assign(size_, {});
    recv_index_.assign(size_, {});
    std::vector<int> send_counts(size_), recv_counts(size_), expected(size_);
    for (int r = 0; r < size_; ++r) {
      std::sort(send[r].begin(), send[r].end());
      std::sort(recv[r].begin(), recv[r].end());
      for (const auto& p : send[r])
        send_index_[r].push_back(p.second);
      for (const auto& p : recv[r])
        recv_index_[r].push_back(p.second);
      send_counts[r] = static_cast<int>(send[r].size());
      recv_counts[r] = static_cast<int>(recv[r].size());
    }
    // Both sides must agree on every pair of ranks: a mismatch would corrupt the halo silently.
    MPI_Alltoall(send_counts.data(), 1, MPI_INT, expected.data(), 1, MPI_INT, comm_);
    int bad = expected != recv_counts;
    MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_INT, MPI_MAX, comm_);
    if (bad) throw std::logic_error("halo plan: the ranks disagree on which particles they share");
    MPI_Allreduce(&owned, &owned_total_, 1, MPI_INT, MPI_SUM, comm_);
    int most = 0;
    MPI_Allreduce(&owned, &most, 1, MPI_INT, MPI_MAX, comm_);
    load_imbalance_ = owned_total_ > 0 ? most / (double(owned_total_) / size_) - 1 : 0;
  }

  // Each halo copy takes its owner's state (the owners' rows, sent in id order).
  void refresh_halo() {
    const double start = MPI_Wtime();
    std::vector<MPI_Request> requests;
    recv_buffer_.resize(size_);
    send_buffer_.resize(size_);
    for (int r = 0; r < size_; ++r)
      if (!recv_index_[r].empty()) {
        recv_buffer_[r].resize(recv_index_[r].size() * kStateRowWidth);
        requests.emplace_back();
        MPI_Irecv(recv_buffer_[r].data(), static_cast<int>(recv_buffer_[r].size()), MPI_DOUBLE, r, 0, comm_,
                  &requests.back());
      }
    for (int r = 0; r < size_; ++r)
      if (!send_index_[r].empty()) {
        local_->read_state_rows(send_index_[r], send_buffer_[r]);
        requests.emplace_back();
        MPI_Isend(send_buffer_[r].data(), static_cast<int>(send_buffer_[r].size()), MPI_DOUBLE, r, 0, comm_,
                  &requests.back());
      }
    MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
    for (int r = 0; r < size_; ++r)
      if (!recv_index_[r].empty()) local_->write_state_rows(recv_index_[r], recv_buffer_[r]);
    communication_seconds_ += MPI_Wtime() - start;
  }

  std::unique_ptr<Engine> local_;
  MPI_Comm comm_ = MPI_COMM_WORLD;
  int rank_ = 0, size_ = 1;
  RowLayout layout_;
  PairRecords pairs_;
  Domain domain_;
  double skin_ = 0;
  double halo_width_ = 0;
  Decomposition decomposition_;
  std::vector<std::vector<int>> send_index_, recv_index_;
  std::vector<std::vector<double>> send_buffer_, recv_buffer_;
  int owned_total_ = 0;
  double communication_seconds_ = 0; // halo refreshes, redistributions, waiting for the slowest rank
  double load_imbalance_ = 0;        // most particles on a rank / mean - 1, at the last redistribution
  long rebalances_ = 0;
};

} // namespace

std::unique_ptr<Engine> make_distributed_engine(std::unique_ptr<Engine> whole, const Domain& domain,
                                                double skin) {
  return std::make_unique<DistributedEngine>(std::move(whole), domain, skin);
}

} // namespace cgdem::parallel

#endif
