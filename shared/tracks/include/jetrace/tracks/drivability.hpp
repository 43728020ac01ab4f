// Can a driver race this track? Checks of a loaded track's geometry against
// its gates and spawns, for `jetrace-track inspect` (docs/TRACKS.md,
// "jetrace-track", "Drivability warnings"). They are warnings, not errors:
// the track still loads and validates, but a car would get stuck, fall or
// miss a gate. Each warning has a stable machine-readable kind.
#pragma once

#include "jetrace/core/track.hpp"
#include "jetrace/core/uniform_grid.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace jetrace {

/// The stable kinds (the `kind` field in `jetrace-track inspect --json`).
inline constexpr const char* kGateUnreachable = "gate_unreachable";
inline constexpr const char* kGateOnObstacle = "gate_on_obstacle";
inline constexpr const char* kGateAboveRoad = "gate_above_road";
inline constexpr const char* kSpawnTooSteep = "spawn_too_steep";
inline constexpr const char* kFacesPointDown = "faces_point_down";
inline constexpr const char* kHeightRange = "height_range";

struct DrivabilityLimits {
    /// Steepest ground a car stands, starts and respawns on (unit: degrees
    /// from the horizontal). On a slope of angle a gravity pulls a car
    /// along the ground at g sin(a) and presses it on at g cos(a); past 45
    /// degrees the pull is larger than the press, so a standing car slides
    /// back (the core's grip is a force limit of that order). A moving car
    /// rides far steeper faces (the up vector follows the contact normal:
    /// the stadium's 85 degree wall), so the reachability of a gate does not
    /// use this limit, only the creases below.
    double ride_limit_deg = 45.0;
    /// Spacing of the ground probes along each leg, in the ground plan (unit: m).
    double sample_spacing_m = 1.0;
    /// Longest stretch of a leg with no surface at all under it (unit: m,
    /// in the ground plan): a jump longer than this falls out of the world.
    double max_gap_m = 12.0;
    /// Highest step up between two probes that a car rolls over (unit: m):
    /// half the car's 2.5 m radius. The contact at a step's edge then pushes
    /// at 60 degrees from the vertical; higher steps stop the car.
    double max_step_up_m = 1.25;
    /// Sharpest concave crease into a face steeper than the ride limit
    /// (unit: degrees between the two faces along the leg). Meeting a crease
    /// of angle f a car keeps cos(f) of its speed along the new face (the
    /// contact is inelastic); past 45 degrees it keeps under 71 %, and the
    /// face then climbs too steeply to gain it back. The stadium's quarter
    /// pipe folds 7 degrees at a time.
    double max_crease_deg = 45.0;
    /// How far the ground at a leg's end may be from the road under its gate
    /// (unit: m, vertically): the leg ended on another floor otherwise.
    double arrive_tolerance_m = 2.0;
    /// A gate whose bottom edge is more than this above the road under it
    /// hangs above the cars (unit: m): a car's centre rides 2.5 m above the
    /// road, so with 0.5 m to spare it passes under.
    double max_gate_lift_m = 3.0;
    /// Share of all faces that may be drivable (by the ride limit) and face
    /// downwards (unit: fraction). Ceilings and the undersides of decks
    /// face down on purpose; a mesh exported with flipped winding has most
    /// of its floors facing down (the physics and the driving AI read faces
    /// either way; renderers that cull back faces draw it inside out).
    double max_down_share = 0.25;
    /// Vertical extent more than this times the larger horizontal one is
    /// implausible (unit: ratio): a Z-up mesh read as Y-up, or a stray vertex.
    double max_height_ratio = 4.0;
    /// Any extent beyond this is implausible (unit: m): a mesh in
    /// centimetres or millimetres read as metres, or a stray vertex.
    double max_extent_m = 100'000.0;
};

/// One warning: its kind, what it concerns, where, and a sentence for people.
struct DrivabilityWarning {
    std::string kind;
    /// "gate", "spawn", "respawn" (a gate's respawn pose: index is the
    /// gate's) or "track" (the whole mesh: index -1).
    std::string subject;
    std::int64_t index = -1;
    Vec3 position{0, 0, 0};
    std::string message;
};

/// Every warning about `track`, gates in order, then spawns, then the mesh.
/// `grid` is built over `track.triangles` (any cell size). A track with a
/// coordinate that is not finite gets one height_range warning and nothing
/// else.
std::vector<DrivabilityWarning> check_drivability(const Track& track, const UniformGrid& grid,
                                                  const DrivabilityLimits& limits = {});

/// The same, building the grid itself (a car radius of 2.5 m).
std::vector<DrivabilityWarning> check_drivability(const Track& track, const DrivabilityLimits& limits = {});

}  // namespace jetrace
