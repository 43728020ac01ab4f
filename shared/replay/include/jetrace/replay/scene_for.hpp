// The scene a replay header names: its track (by name, or the one the user
// gave), loaded once, with the header's tick rate.
#pragma once

#include "jetrace/replay/verify.hpp"

#include <functional>
#include <string>

namespace jetrace::replay {

/// Loads the track `spec` names into `out`; false with a reason.
using TrackLoader = std::function<bool(const std::string& spec, Track& out, std::string& error)>;

/// A SceneFor that loads `track_spec` (or, if empty, the header's track
/// name) with `load` the first time it is asked, and keeps it.
SceneFor scene_for(TrackLoader load, std::string track_spec = {});

}  // namespace jetrace::replay
