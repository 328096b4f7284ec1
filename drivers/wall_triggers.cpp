#include "drivers/wall_triggers.hpp"
#include <cmath>
#include <cstdio>
#include <string>

namespace cgdem {

WallTriggers::WallTriggers(Scene& scene) : scene_(scene) {
  for (std::size_t w = 0; w < scene_.walls.size(); ++w)
    for (int k = -1; k < static_cast<int>(scene_.walls[w].then.size()); ++k)
      if (scene_.walls[w].segment(k).until_force > 0) triggers_.push_back({static_cast<int>(w), k});
}

long WallTriggers::next_check(long step, double dt, long limit) const {
  const double now = step * dt;
  for (const Trigger& t : triggers_) {
    const WallSpec::Segment s = scene_.walls[std::size_t(t.wall)].segment(t.segment);
    if (t.ended || now >= s.stop) continue;
    // Checks start with the segment's first step.
    const long first = std::max(step + 1, static_cast<long>(std::ceil(s.start / dt - 1e-9)));
    limit = std::min(limit, now >= s.start ? step + kCheckEvery : first);
  }
  return limit;
}

void WallTriggers::check(Engine& engine, std::vector<std::unique_ptr<Analysis>>& analyses) {
  const double now = engine.time();
  Observables obs;
  bool observed = false;
  for (Trigger& t : triggers_) {
    const WallSpec::Segment s = scene_.walls[std::size_t(t.wall)].segment(t.segment);
    if (t.ended || now <= s.start || now > s.stop) continue;
    if (!observed) obs = engine.observe(), observed = true;
    // The particles' force on the wall against the segment's velocity.
    const double speed = std::sqrt(s.velocity[0] * s.velocity[0] + s.velocity[1] * s.velocity[1] +
                                   s.velocity[2] * s.velocity[2]);
    double against = 0;
    for (int a = 0; a < 3; ++a)
      against -= obs.wall_force[3 * std::size_t(t.wall) + a] * s.velocity[a] / speed;
    if (against < s.until_force) continue;
    end(t, now, engine, analyses);
    const std::string which = t.segment < 0 ? "motion" : "motion.then." + std::to_string(t.segment);
    std::fprintf(
        stderr,
        "\nt = %.6g s: the particles push wall '%s' with %.4g N against its %s (until_force %.4g N): "
        "it holds its position from here\n",
        now, scene_.walls[std::size_t(t.wall)].name.c_str(), against, which.c_str(), s.until_force);
  }
}

void WallTriggers::end(Trigger& t, double time, Engine& engine,
                       std::vector<std::unique_ptr<Analysis>>& analyses) {
  WallSpec& w = scene_.walls[std::size_t(t.wall)];
  w.end_segment(t.segment, time);
  engine.end_wall_segment(t.wall, t.segment, time);
  for (auto& a : analyses)
    a->wall_motion_changed(w);
  t.ended = true;
  t.ended_at = time;
}

void WallTriggers::save(CheckpointData& c) const {
  std::vector<double> ends;
  for (const Trigger& t : triggers_)
    if (t.ended) ends.insert(ends.end(), {double(t.wall), double(t.segment), t.ended_at});
  if (!ends.empty()) c.reals["wall_segment_ends"] = ends;
}

void WallTriggers::load(const CheckpointData& c, Engine& engine,
                        std::vector<std::unique_ptr<Analysis>>& analyses) {
  const auto it = c.reals.find("wall_segment_ends");
  if (it == c.reals.end()) return;
  for (std::size_t e = 0; e + 2 < it->second.size(); e += 3)
    for (Trigger& t : triggers_)
      if (!t.ended && t.wall == int(it->second[e]) && t.segment == int(it->second[e + 1]))
        end(t, it->second[e + 2], engine, analyses);
}

} // namespace cgdem
