// What the viewer sends a page (docs/VIEWER.md, "Messages"): a hello with
// the track's gates, the cars and the timeline, then a frame per shown
// tick. Positions are the core's doubles, written so that they read back
// bit for bit (JSON numbers are doubles in the page too).
#pragma once

#include "json_parts.hpp"
#include "playback.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace jetrace::view {

/// The first message to a page.
std::string hello_json(const Playback& p);
/// The world at the tick `p` shows, with standings, phase and the ghosts.
std::string frame_json(const Playback& p);
/// The race phase at `s`: "countdown", "racing" or "finished".
std::string phase_of(const ReplayPlayer& r, const WorldState& s);

}  // namespace jetrace::view
