#pragma once
// Motion segments that end when the particles push back (`until_force` in a wall's motion): a piston that
// loads a bed at constant speed until a target stress (times its area), then holds its position until
// its next segment starts, as Thakur et al. load each bed to 40 kPa whatever its stiffness.
#include <memory>
#include <vector>
#include "core/frame.hpp"
#include "core/scene.hpp"
#include "drivers/analyses.hpp"
#include "kernels/engine.hpp"

namespace cgdem {

class WallTriggers {
public:
  // The force on a wall is checked every this many steps while a segment with until_force is moving: the
  // piston overshoots by at most this many steps of its travel.
  static constexpr long kCheckEvery = 10;

  // `scene` outlives this and is the one the run uses: an ended segment is ended in it too.
  explicit WallTriggers(Scene& scene);
  // The step to stop at for the next check (`limit` when no check comes sooner).
  long next_check(long step, double dt, long limit) const;
  // After the engine's last step: ends every armed segment whose wall the particles push against its
  // velocity with at least its until_force, in the engine, the scene and the analyses; one line on
  // stderr each.
  void check(Engine& engine, std::vector<std::unique_ptr<Analysis>>& analyses);
  // The segments ended so far, in a checkpoint (reals "wall_segment_ends": wall, segment, time each), and
  // back: a restart ends those that its scene still gives an until_force.
  void save(CheckpointData& c) const;
  void load(const CheckpointData& c, Engine& engine, std::vector<std::unique_ptr<Analysis>>& analyses);

private:
  struct Trigger {
    int wall = 0, segment = 0; // segment -1: the wall's first motion
    bool ended = false;
    double ended_at = 0;
  };
  void end(Trigger& t, double time, Engine& engine, std::vector<std::unique_ptr<Analysis>>& analyses);
  std::vector<Trigger> triggers_;
  Scene& scene_;
};

} // namespace cgdem
