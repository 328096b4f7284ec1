#pragma once
// Asynchronous HDF5 + XDMF result output.
//
// The engine hands host copies (core/frame.hpp) to write_frame / write_series, which queue them and
// return at once; a single oneTBB task (one writer at a time, in submission order) writes them while the
// device keeps stepping. flush() waits for the queue; the destructor flushes and closes.
//
// Layout of <stem>.h5 (SI units):
//   root attributes  cgdem_version, scene, backend, scaling_law (strings), threads (int32),
//                    time_step, scale_factor (double), frames_complete, series_complete (int64),
//                    fields (string, comma separated), wall_names (string, comma separated)
//   /frames/NNNNNN/  attributes time (double), step (int64); datasets id (N, int64), position (N x 3),
//                    velocity (N x 3), angular_velocity (N x 3), radius (N), mass (N) (double),
//                    group (N, int32). position, radius and id are always written, the others if asked.
//   /series/         1-D extendible datasets time, step (int64), kinetic_energy, rotational_energy,
//                    contacts (int64), one per analysis key (created on first appearance, earlier rows
//                    NaN; a row without the key also reads NaN), wall_force/<wall> (T x 3) and
//                    wall_torque/<wall> (T x 3: moment about the wall's point; NaN when not given).
// <stem>.xdmf beside it: a temporal collection of Polyvertex grids naming only committed frames.
//
// Kill safety: the visible <stem>.h5 is never opened for writing. Each batch of queued work is applied to
// a shadow copy (<stem>.h5.shadow, which lags the visible file by one batch), the shadow is closed and
// fsync'ed, then the two names are exchanged atomically (renameat2 RENAME_EXCHANGE, or link + rename).
// Hence at any instant, including after SIGKILL or a crash mid-write, <stem>.h5 is a cleanly closed HDF5
// file holding a prefix of the submitted frames and series rows, and the XDMF (rewritten via tmp + rename
// after each exchange) names only frames present in it. Costs: every batch is written twice and the
// shadow uses as much disk as the result until close() deletes it.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/frame.hpp"

namespace cgdem {

// Process-wide lock for every HDF5 call made by cgdem (writer task, checkpoints, tests reading files).
std::mutex& hdf5_mutex();

class ResultWriter {
public:
  // Creates <h5_path> (replacing any previous file) with the root attributes and empty /frames and /series,
  // its shadow, and an empty <stem>.xdmf. fields: any of id, position, velocity, angular_velocity, radius,
  // mass, group (id, position and radius are always written). Throws std::invalid_argument for an unknown
  // field and std::runtime_error naming the path if the files cannot be created.
  ResultWriter(const std::string& h5_path, const RunInfo& info, const std::vector<std::string>& fields);
  // Flushes and closes; an error not yet reported is printed to stderr (destructors do not throw).
  ~ResultWriter();
  ResultWriter(const ResultWriter&) = delete;
  ResultWriter& operator=(const ResultWriter&) = delete;

  // Queue one frame (becomes /frames/<next index>) and return at once. Throws std::invalid_argument if an
  // array that will be written has the wrong size, std::runtime_error if the writer already failed or is
  // closed.
  void write_frame(FrameData frame);
  // Queue one series row and return at once. wall_force must hold 3 values per RunInfo::wall_names entry;
  // analysis keys must be non-empty, without '/', and not one of the built-in series names.
  void write_series(SeriesRow row);

  // Wait until everything queued is written and visible. Rethrows a writer error (once) as
  // std::runtime_error naming the path; later write_* calls then throw.
  void flush();
  // flush(), then remove the shadow. Idempotent; write_* afterwards throw.
  void close();

  std::size_t pending() const;         // queued or in-progress items not yet visible in the file
  std::int64_t frames_written() const; // frames visible in <h5_path> (== root attribute frames_complete)
  const std::string& path() const;
  const std::string& xdmf_path() const;

  // Testing hook: called on the writer thread before each batch is written (not under any lock).
  void set_before_write_hook(std::function<void()> hook);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// <dir>/<stem>.xdmf for <dir>/<stem>.h5 (any extension is replaced).
std::string xdmf_path_for(const std::string& h5_path);

} // namespace cgdem
