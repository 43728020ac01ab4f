// Pieces of the JSON sent to pages, shared by the replay frames
// (world_json.cpp) and the live ones (live_json.cpp): positions as the
// core's doubles, directions and speeds rounded, the track's gates.
#pragma once

#include "jetrace/core/track.hpp"
#include "jetrace/core/world.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace jetrace::view::json_parts {

using nlohmann::json;

/// Names and paths are untrusted bytes (player names carry no encoding):
/// invalid UTF-8 becomes U+FFFD instead of an exception.
std::string text_of(const json& j);
/// [x, y, z] with every bit of the doubles.
json vec(const Vec3& v);
/// `v` to the nearest multiple of `step`.
double rounded(double v, double step);
/// A unit vector rounded to 1e-4 (enough for drawing, fewer bytes).
json unit(const Vec3& v);
/// A time in s rounded to 1 ms, or null.
json optional_s(const std::optional<double>& v);
/// {name, triangles, gates, bounds} of the hello.
json track_json(const Track& t);
/// One car of a frame: slot, p, f, u, speed, lap, gate, finished.
json car_json(const CarState& c, std::size_t slot);

}  // namespace jetrace::view::json_parts

namespace jetrace::view {
/// The track's triangles for drawing: 9 little-endian float32 per triangle
/// (a, b, c, each x y z), served as /track.bin.
std::vector<std::uint8_t> track_mesh_bytes(const Track& track);
}  // namespace jetrace::view
