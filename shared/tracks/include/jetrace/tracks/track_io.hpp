// Loading tracks: built-in names or Wavefront OBJ files (see docs/TRACKS.md
// for the OBJ convention). Everything read from a file is checked; problems
// come back as an error message, never an assert or a crash.
#pragma once

#include "jetrace/core/track.hpp"
#include "jetrace/tracks/mesh_import.hpp"
#include "jetrace/tracks/track_manifest.hpp"

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

/// Reads and imports an OBJ file (refused before reading when larger than
/// kMaxTrackFileBytes).
bool import_obj_file(const std::string& path, Track& out, std::string& error);

/// OBJ text as a plain mesh: one part per group name (sorted by name), no
/// convention; what a manifest reads an .obj mesh with.
bool import_obj_mesh(std::string_view text, ImportedMesh& out, std::string& error);

/// A mesh file by its extension: .gltf, .glb or .obj (import_obj_mesh).
bool import_mesh_file(const std::string& path, ImportedMesh& out, std::string& error);

/// `spec` is a built-in track name, a path to an .obj file (the convention
/// above), to a track manifest (.json) or to a compiled track (.jtrack, or
/// any file starting with its magic; jtrack.hpp). A bare .gltf/.glb is refused: it
/// has no gates, so it needs a manifest.
bool load_track(const std::string& spec, Track& out, std::string& error);
bool load_track_report(const std::string& spec, Track& out, TrackReport& report, std::string& error);

/// As load_track(), but a bare .gltf/.glb is read as a mesh without gates or
/// spawns (every part, degenerate triangles dropped): what
/// `jetrace-track inspect` and `render` show. The track then does not validate.
bool inspect_track(const std::string& spec, Track& out, TrackReport& report, std::string& error);

}  // namespace jetrace
