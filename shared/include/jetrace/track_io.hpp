// Loading tracks: built-in names or Wavefront OBJ files (see docs/TRACKS.md
// for the OBJ convention). Everything read from a file is checked; problems
// come back as an error message, never an assert or a crash.
#pragma once

#include "jetrace/track.hpp"

#include <string>
#include <string_view>

namespace jetrace {

/// Parses OBJ text following the jetrace convention. Returns false and sets
/// `error` (naming the problem, with a line number where there is one) on
/// bad input. `name` becomes the track's name.
bool import_obj(std::string_view text, const std::string& name, Track& out, std::string& error);

/// Writes `track` as OBJ text following the same convention: the `track`
/// group (every triangle, vertices shared), one `checkpoint_N` quad per gate
/// (wound so its right-hand-rule normal is the direction of travel), one
/// `spawn_N` triangle per spawn (centroid on the surface, first vertex ahead)
/// and `kill_height`. Coordinates are written exactly (shortest round-trip
/// form), so import_obj(export_obj(t)) gives t's triangles bit for bit; gates,
/// spawns and respawn poses are re-derived and agree to rounding.
std::string export_obj(const Track& track);

/// Reads and imports an OBJ file.
bool import_obj_file(const std::string& path, Track& out, std::string& error);

/// `spec` is a built-in track name or a path to an .obj file.
bool load_track(const std::string& spec, Track& out, std::string& error);

}  // namespace jetrace
