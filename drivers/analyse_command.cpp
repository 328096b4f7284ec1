#include "drivers/analyse_command.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <set>

#include "drivers/preflight.hpp"
#include "drivers/scene_parser.hpp"

namespace cgdem {

std::vector<AnalysedFrame> analyse_frames(const std::vector<std::string>& files,
                                          std::vector<std::unique_ptr<Analysis>>& analyses, long frame_every,
                                          long end_step) {
  std::vector<AnalysedFrame> out;
  long last_step = -1;
  for (const std::string& path : files) {
    const ResultReader file(path);
    const std::vector<std::int64_t>& rows = file.series_step();
    std::size_t row = 0;
    for (std::size_t k = 0; k < file.frames(); ++k) {
      const FrameData frame = file.frame(k);
      if (frame.step <= last_step) continue;
      // The series row written with this frame (the same output): the wall forces at this step.
      while (row < rows.size() && rows[row] < frame.step)
        ++row;
      if (row == rows.size() || rows[row] != frame.step)
        throw std::runtime_error("result file '" + path + "': no series row for the frame of step " +
                                 std::to_string(frame.step));
      AnalysedFrame a;
      a.time = frame.time;
      a.step = frame.step;
      const bool output_step = frame.step % frame_every == 0 || frame.step == end_step;
      run_analyses(analyses,
                   AnalysisInput{frame, frame.time, file.wall_names(), file.wall_force(row), output_step},
                   a.outputs);
      out.push_back(std::move(a));
      last_step = frame.step;
    }
  }
  return out;
}

const char* analyse_help() {
  return R"(Usage: cgdem analyse RUN.h5 [MORE.h5 ...] [options]

Evaluates a scene's analyses (docs/scene_format.md, "analyses") again over the saved frames of a run, as
the run evaluated them at each output, and prints every output at the last frame: to try another fit or
window (--set analyses.0.average_from=2), to add an analysis the run did not have (--scene), or to read a
run whose analysis has changed since it ran. Nothing is simulated; only the frames are read.

Several files are the parts of one run continued from checkpoints, in order (a sweep's
runs/<run>/run.part1.h5 ... run.h5); frames that a continued part repeats are read once.

Options:
  --scene SCENE.yaml    take the analyses from this scene (default: the scene stored in the first file,
                        as the run resolved it)
  --set key.path=value  override in that scene before its analyses are built (repeatable)
  --csv FILE            also write every output at every frame (columns time, step, then the outputs)
  --help                this text

What the frames hold limits what can be recomputed: the wall forces come from the file's series (the
force each named wall felt at that output); an analysis of velocities needs frames written with them
(output.fields). A wall segment that ended at a force (until_force) is assumed to have run to its stop
time, so strains measured after such an end follow the scene's schedule, not the wall. An analysis that
writes its own file (a profile's or a distribution's `csv`) writes it again: give it another name with
--set analyses.N.csv=FILE to keep the run's.

Examples:
  cgdem analyse drum.h5 --set analyses.0.cell_width=0.003 --csv angles.csv
  cgdem analyse runs/reference_s1/run.part1.h5 runs/reference_s1/run.part2.h5 runs/reference_s1/run.h5
)";
}

int analyse_command(const std::vector<std::string>& args) {
  std::vector<std::string> files, overrides;
  std::string scene_path, csv;
  for (std::size_t k = 0; k < args.size(); ++k) {
    const std::string& a = args[k];
    if (a == "--help" || a == "-h") {
      std::cout << analyse_help();
      return 0;
    }
    if (a == "--scene" || a == "--set" || a == "--csv") {
      if (k + 1 >= args.size()) {
        std::cerr << "cgdem analyse: option " << a << " needs a value (see --help)\n";
        return exit_bad_input;
      }
      const std::string& v = args[++k];
      if (a == "--scene")
        scene_path = v;
      else if (a == "--set")
        overrides.push_back(v);
      else
        csv = v;
    } else if (a.rfind("--", 0) == 0) {
      std::cerr << "cgdem analyse: unknown option '" << a << "' (see --help)\n";
      return exit_bad_input;
    } else {
      files.push_back(a);
    }
  }
  if (files.empty()) {
    std::cerr << "cgdem analyse: no result file given (see --help)\n";
    return exit_bad_input;
  }
  try {
    const ResultReader first(files.front());
    const Scene scene = scene_path.empty() ? parse_scene_text(first.scene_yaml(), files.front(), overrides)
                                           : parse_scene_file(scene_path, overrides);
    std::vector<std::unique_ptr<Analysis>> analyses = make_analyses(scene);
    if (analyses.empty()) {
      std::cerr << "cgdem analyse: " << (scene_path.empty() ? files.front() : scene_path)
                << ": the scene has no analyses; add them with --scene or --set analyses=[...]\n";
      return exit_bad_input;
    }
    for (const WallSpec& w : scene.walls)
      for (int s = -1; s < static_cast<int>(w.then.size()); ++s)
        if (w.segment(s).until_force > 0)
          std::fprintf(stderr,
                       "cgdem analyse: note: wall '%s' has a segment that ends at a force; strains assume it "
                       "ran to its stop time\n",
                       w.name.c_str());
    const double dt = first.time_step();
    const long end_step = static_cast<long>(std::ceil(scene.time.end / dt - 1e-9));
    const long frame_every =
        scene.output.every > 0 ? std::max(1L, std::lround(scene.output.every / dt)) : end_step;
    const std::vector<AnalysedFrame> frames = analyse_frames(files, analyses, frame_every, end_step);
    if (frames.empty()) {
      std::cerr << "cgdem analyse: " << files.front() << ": no frames\n";
      return exit_bad_input;
    }
    if (!csv.empty()) {
      std::set<std::string> keys;
      for (const AnalysedFrame& f : frames)
        for (const auto& [key, value] : f.outputs)
          keys.insert(key);
      std::ofstream out(csv);
      out.precision(17);
      out << "time,step";
      for (const std::string& key : keys)
        out << "," << key;
      out << "\n";
      for (const AnalysedFrame& f : frames) {
        out << f.time << "," << f.step;
        for (const std::string& key : keys) {
          const auto it = f.outputs.find(key);
          out << ",";
          if (it != f.outputs.end()) out << it->second;
        }
        out << "\n";
      }
      if (!out.flush()) {
        std::cerr << "cgdem analyse: cannot write '" << csv << "'\n";
        return exit_write_failed;
      }
    }
    const AnalysedFrame& last = frames.back();
    std::fprintf(stderr, "cgdem analyse: %zu frames in %zu file(s), t = %.6g to %.6g s\n", frames.size(),
                 files.size(), frames.front().time, last.time);
    for (const auto& [key, value] : last.outputs)
      std::printf("%s %.17g\n", key.c_str(), value);
    return 0;
  } catch (const SceneError& e) {
    std::cerr << "cgdem analyse: " << e.what() << "\n";
    return exit_bad_input;
  } catch (const std::exception& e) {
    std::cerr << "cgdem analyse: " << e.what() << "\n";
    return exit_bad_input;
  }
}

} // namespace cgdem
