#pragma once
// `cgdem analyse`: a scene's analyses evaluated again over the frames of a finished (or killed) run, as the
// run evaluated them at each output: with other parameters (--set analyses.0.cell_width=...), another
// scene's analyses (--scene), or on the parts of a run continued from checkpoints (several files in
// order). LAMMPS users know the idea as `rerun`; here nothing is integrated, only the analyses read the
// frames.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/result_reader.hpp"
#include "drivers/analyses.hpp"

namespace cgdem {

// Every output of `analyses` at each frame of `files` (the parts of one run, in order; a frame whose step
// is not after the last one evaluated is skipped: a run continued from a checkpoint repeats the frames
// from it on). A frame counts in running means and peaks when it is one of the run's output steps
// (step a multiple of `frame_every`, or `end_step`), as in the run. Throws std::runtime_error naming the
// file for a file that cannot be read, and for a frame without its series row (the wall forces).
struct AnalysedFrame {
  double time = 0;
  long step = 0;
  std::map<std::string, double> outputs;
};
std::vector<AnalysedFrame> analyse_frames(const std::vector<std::string>& files,
                                          std::vector<std::unique_ptr<Analysis>>& analyses, long frame_every,
                                          long end_step);

int analyse_command(const std::vector<std::string>& args);
const char* analyse_help();

} // namespace cgdem
