// What a live page is sent (docs/VIEWER.md, "Live and drive modes"): a
// hello like the replay's (mode "drive" or "live", no timeline), then
// frames of the client's world: the own car where the client draws it
// (prediction plus the fading correction), the others interpolated.
#pragma once

#include "live_race.hpp"

#include <string>

namespace jetrace::view {

std::string live_hello_json(const LiveRace& s);
std::string live_frame_json(const LiveRace& s);

}  // namespace jetrace::view
