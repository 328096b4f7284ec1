#pragma once
// Reads back a cgdem result file, the layout core/result_writer.hpp writes: the root attributes (the
// resolved scene, the time step, the named walls), every complete frame in order, and the series' time,
// step and wall forces. `cgdem analyse` evaluates a scene's analyses over the frames with it.
#include <cstdint>
#include <string>
#include <vector>

#include "core/frame.hpp"
#include "core/hdf5_support.hpp"

namespace cgdem {

class ResultReader {
public:
  // Opens the file and reads its attributes and series; throws std::runtime_error naming the path when it
  // is not a cgdem result (no scene or time step attribute, no /frames) or cannot be read.
  explicit ResultReader(const std::string& path);
  ~ResultReader(); // closes the file under the process-wide HDF5 lock
  ResultReader(const ResultReader&) = delete;
  ResultReader& operator=(const ResultReader&) = delete;

  const std::string& path() const { return path_; }
  const std::string& scene_yaml() const { return scene_yaml_; }
  double time_step() const { return time_step_; }
  const std::vector<std::string>& wall_names() const { return wall_names_; }

  // Frames the file holds (its `frames_complete`: frames written after a crash are not counted).
  std::size_t frames() const { return frames_; }
  // Frame k (/frames/NNNNNN): its time and step, and the fields the run wrote; a field left out by the
  // scene's output.fields stays empty.
  FrameData frame(std::size_t k) const;

  // The series, one row per output (`series_complete` rows): time, step, and the force the particles
  // exerted on each named wall (3 per wall, in wall_names() order).
  const std::vector<double>& series_time() const { return series_time_; }
  const std::vector<std::int64_t>& series_step() const { return series_step_; }
  std::vector<double> wall_force(std::size_t row) const;

private:
  std::string path_, scene_yaml_;
  double time_step_ = 0;
  std::vector<std::string> wall_names_;
  std::size_t frames_ = 0;
  std::vector<double> series_time_;
  std::vector<std::int64_t> series_step_;
  std::vector<std::vector<double>> wall_force_; // per named wall: rows x 3
  h5::Hid file_;
};

} // namespace cgdem
