// Track manifests: a JSON file beside any mesh (glTF or OBJ) that says how to
// make a raceable track of it without editing it in a modeller: which files,
// scale and up axis, which parts are drivable, a route (a closed centre line)
// from which gates and spawns are generated, or explicit gates, and the kill
// height. Every key, its unit and default: docs/TRACKS.md, "Track manifests".
#pragma once

#include "jetrace/core/track.hpp"
#include "jetrace/tracks/mesh_import.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace jetrace {

/// A point on the road: x and z, and y when the manifest gives it.
struct RoutePoint {
    double x = 0, z = 0;
    std::optional<double> y;
};

/// A gate the manifest places itself: where (on the road), which way.
struct ManifestGate {
    RoutePoint position;
    /// Direction of travel (x, z), or none: the route's tangent.
    std::optional<Vec3> direction;
    /// Full width and height (unit: m); 0: taken from the road.
    double width_m = 0, height_m = 0;
};

enum class RouteSurface { lowest, highest };

struct TrackManifest {
    std::string name;
    /// Mesh files, resolved against the manifest's folder.
    std::vector<std::string> meshes;
    double scale = 1;
    /// The mesh's up axis: 'y' (glTF's) or 'z' (rotated to Y up).
    char up = 'y';
    std::vector<std::string> drivable{"*"}, ignore;
    /// Closed centre line (the last point joins the first); first point = start line.
    std::vector<RoutePoint> route;
    RouteSurface route_surface = RouteSurface::lowest;
    double gate_spacing_m = 40;
    double gate_width_m = 30;   // largest full width of a generated gate
    double gate_height_m = 12;  // largest full height of a generated gate
    std::vector<ManifestGate> gates;
    int spawn_count = 8;
    double spawn_row_spacing_m = 10, spawn_column_spacing_m = 6, spawn_back_m = 12;
    std::optional<double> kill_height_m;
};

/// What loading found beyond the track itself (jetrace-track inspect).
struct TrackReport {
    std::string format;  // "builtin", "obj", "gltf" or "manifest"
    std::size_t source_triangles = 0;
    std::size_t degenerate_dropped = 0;  // zero-area triangles dropped (OBJ: counted, kept)
    std::size_t ignored_triangles = 0;   // parts the manifest does not make drivable
    std::size_t skipped_primitives = 0;  // glTF primitives that are not triangle lists
    std::vector<Vec3> route;             // the route on the road surface, closed
    double route_length_m = 0;
    std::vector<std::string> warnings;
};

/// Largest manifest file read (unit: bytes).
inline constexpr std::size_t kMaxManifestBytes = std::size_t{1} << 24;

/// Parses manifest JSON; mesh paths are resolved against `dir`.
bool parse_manifest(std::string_view json, const std::string& dir, TrackManifest& out, std::string& error);

/// Builds the track from a parsed manifest and its meshes (one per
/// manifest.meshes entry, in order): parts filtered, scaled, degenerate
/// triangles dropped, gates and spawns generated and checked.
bool build_manifest_track(const TrackManifest& manifest, const std::vector<ImportedMesh>& meshes, Track& out,
                          TrackReport& report, std::string& error);

/// Only the first half of build_manifest_track(): the drivable mesh, without
/// gates or spawns (the track does not validate).
bool build_mesh_track(const TrackManifest& manifest, const std::vector<ImportedMesh>& meshes, Track& out,
                      TrackReport& report, std::string& error);

/// Reads a manifest file and its meshes, then build_manifest_track().
bool load_manifest_file(const std::string& path, Track& out, TrackReport& report, std::string& error);

}  // namespace jetrace
