// Measurements on the lab scenes (issue 4): each returns numbers, the tests
// assert on them and jetrace-bench study writes them to CSV.
#pragma once

#include "lab/scenes.hpp"

#include <functional>
#include <vector>

namespace jetrace::lab {

// --------------------------------------------------------------- tunnelling

/// The thin-wall scene: a floor and a zero-thickness wall at x = 0 (tessellated
/// in 4 m squares, so hits land on edges and seams too).
Mesh thin_wall_mesh();

/// Approach grid for one speed: `phases` start offsets spread over one step's
/// travel (the first at r + epsilon from the wall, where a push-out leaves a
/// car), times `laterals` offsets along the wall across one 4 m square.
struct Approach {
    int phases = 16;
    int laterals = 4;
};

/// Start of the car's centre for approach (`phase`, `lateral`) at `speed_mps`.
Vec3 approach_start(const PhysicsSettings& ps, double speed_mps, const Approach& a, int phase, int lateral);

/// Steps a car is followed after its start (it reaches the wall in the first).
inline constexpr int kApproachSteps = 8;

/// A car sliding on the floor at `speed_mps` towards the wall (no throttle):
/// true if, for any approach, its centre ever ends a step beyond the wall.
bool passes_through(const Scene& scene, double speed_mps, const Approach& a);

struct TunnelLimit {
    /// Highest probed speed up to which no probed speed passes (unit: m/s).
    double holds_to_mps = 0;
    /// Lowest probed speed that passes, or 0 if none up to the maximum (unit: m/s).
    double first_pass_mps = 0;
};

/// Probes speeds from `lo_mps` up by `ratio` (geometric) to `hi_mps`, then
/// bisects between the last holding and first passing speed to `tol_mps`.
/// `passes(speed)` says whether a car at that speed passes through.
TunnelLimit tunnelling_limit(const std::function<bool(double)>& passes, double lo_mps, double hi_mps,
                             double ratio = 1.05, double tol_mps = 0.5);
/// The same for a jetrace scene (passes_through with approach grid `a`).
TunnelLimit tunnelling_limit(const Scene& scene, double lo_mps, double hi_mps, const Approach& a,
                             double ratio = 1.05, double tol_mps = 0.5);

// ------------------------------------------------------------------- spring

struct SpringRun {
    /// Largest and final total energy over the run, relative to the start.
    double max_energy_ratio = 0;
    double final_energy_ratio = 0;
};

/// An undamped unit-mass spring (x'' = -omega^2 x) stepped `steps` times with
/// the core's own integrate(): velocity first from the acceleration at the
/// step's start (as apply_controls_and_forces does), then the position.
SpringRun spring(Integrator integrator, int tick_rate_hz, double omega_radps, long steps);

// -------------------------------------------------------------------- seams

struct SeamRun {
    /// Largest |height - height of the same run on a floor of two triangles|
    /// at the same step (unit: m). For a slide at rest height the reference
    /// height is constant, so this is the vertical excursion.
    double max_excursion_m = 0;
    /// Largest |speed - speed of the reference run| at the same step (unit: m/s).
    double max_speed_change_mps = 0;
    /// Final speed of the reference run (unit: m/s).
    double reference_speed_mps = 0;
    int steps = 0;
};

/// A car sliding at `speed_mps` (heading `heading_deg` from +X, no throttle)
/// for `seconds` over a floor split into squares of `cell_m`, from a height
/// `drop_m` above rest with vertical speed `vy_mps` (0, 0: sliding at rest
/// height; else a landing).
SeamRun slide_over_seams(const PhysicsSettings& ps, double cell_m, double speed_mps, double heading_deg,
                         double seconds, double drop_m = 0.0, double vy_mps = 0.0);

// ------------------------------------------------------------------- corner

/// A pit: floor and four walls meeting in corners, each face a fan of thin
/// triangles around the corner, so a car in a corner touches many at once.
Mesh corner_mesh();

struct CornerRun {
    /// Car-steps driven.
    int steps = 0;
    /// Steps where the pass cap stopped the resolver with the car inside.
    int capped_steps = 0;
    /// Steps that ended with the car inside geometry (distance < r - 1e-6).
    int inside_steps = 0;
    /// Steps that ended inside geometry while the resolver was not capped.
    int inside_uncapped_steps = 0;
    /// Deepest penetration at the end of a step (unit: m).
    double worst_penetration_m = 0;
    /// Most push-outs in one step.
    int max_pushes = 0;
    /// Most pushing passes in one step.
    int max_passes = 0;
};

/// Cars driven at full throttle into the pit's corners from many headings
/// and speeds up to `max_speed_mps`, `seconds` each.
CornerRun drive_into_corners(const PhysicsSettings& ps, double max_speed_mps, int headings, double seconds);

}  // namespace jetrace::lab
