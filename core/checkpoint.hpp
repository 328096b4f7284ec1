#pragma once
// Restart checkpoints: one HDF5 file holding a CheckpointData (core/frame.hpp) exactly.
//
// Layout: root attributes format ("cgdem-checkpoint"), format_version (int32, 1), time (double),
// step (int64), scene (string); /reals/<name> (1-D double), /ints/<name> (1-D int64),
// /scalars/<name> (scalar double). Doubles are stored as IEEE little-endian and read back bit for bit
// (NaN payloads and signed zeros included). Names must be non-empty and contain no '/'.
#include <string>

#include "core/frame.hpp"

namespace cgdem {

// Writes <path>.tmp, fsyncs it, renames it over <path> and fsyncs the directory: <path> is always either
// the previous checkpoint or the new one, never a partial file. Throws std::runtime_error naming the path.
void write_checkpoint(const std::string& path, const CheckpointData& data);

// Reads a checkpoint written by write_checkpoint. Throws std::runtime_error naming the path if the file is
// missing, is not a cgdem checkpoint, or is damaged.
CheckpointData read_checkpoint(const std::string& path);

} // namespace cgdem
