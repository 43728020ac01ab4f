// jetrace-sim --replay FILE --svg OUT.svg: a top-down picture of the
// replay's track (jetrace-track render's, tools/track/track_svg.hpp) with
// every car's line over the race coloured by its speed.
#pragma once

#include "sim_replay.hpp"

#include <string>

namespace jetrace::sim {

/// Re-simulates `path` and writes the picture to `svg_path`, `width_px`
/// wide. Exit 0 written; 1 the replay is damaged (a replay that merely ends
/// early is drawn up to there, with a warning) or the file cannot be
/// written; 2 the replay cannot be read at all.
int svg_file(const std::string& path, const ReplayArgs& args, const std::string& svg_path, int width_px);

}  // namespace jetrace::sim
