// Built-in tracks, generated from a few parameters.
#pragma once

#include "jetrace/core/track.hpp"

#include <string>
#include <vector>

namespace jetrace {

/// An oval circuit inside a stadium: two straights joined by half circles,
/// concrete barriers along both edges, a tessellated floor, outer walls and,
/// optionally, the seed's 1 km wall at 85 degrees before the start/finish
/// line with a gate at its top.
struct OvalParams {
    std::string name = "stadium";
    /// Length of each straight (unit: m).
    double straight_m = 1200;
    /// Radius of the turns' centre line (unit: m).
    double turn_radius_m = 150;
    /// Width between the barriers (unit: m).
    double width_m = 40;
    /// Height of the barriers (unit: m).
    double barrier_height_m = 4;
    /// Edge of the floor's squares (unit: m).
    double floor_cell_m = 35;
    /// Segments per half-circle turn.
    int turn_segments = 16;
    /// Build the wall on the first straight.
    bool wall = true;
    /// Distance along the straight where the wall's quarter-pipe starts (unit: m).
    double wall_start_m = 250;
    /// Radius of the quarter-pipe from floor to wall (unit: m).
    double wall_curve_radius_m = 40;
    /// Length of the flat part of the wall along its surface (unit: m).
    double wall_length_m = 1000;
    /// Slope of the wall (unit: degrees).
    double wall_angle_deg = 85;
    /// Start/finish line distance along the first straight (unit: m).
    double finish_line_m = 1100;
    /// Spawn slots (4 columns).
    int spawn_slots = 64;
};

OvalParams stadium_params();
/// A small oval without the wall for quick races and tests (lap about 450 m).
OvalParams ring_params();

Track make_oval(const OvalParams& p);

/// Names of the built-in tracks.
std::vector<std::string> builtin_track_names();
/// True and fills `out` if `name` is a built-in track.
bool make_builtin_track(const std::string& name, Track& out);

/// make_builtin_track() with a reason when `spec` names no built-in track
/// (a replay::TrackLoader of the built-in tracks only).
bool load_builtin(const std::string& spec, Track& out, std::string& error);

}  // namespace jetrace
