// A hovercar: the simulated state of one car, its input, and the phases of
// its step that do not involve the track (controls, forces, friction,
// integration, alignment).
#pragma once

#include "jetrace/core/contacts.hpp"
#include "jetrace/core/math.hpp"
#include "jetrace/core/settings.hpp"
#include "jetrace/core/track.hpp"

#include <cstdint>

namespace jetrace {

/// One tick of a driver's controls, quantised to small integers so that a
/// client and the server step with identical values.
struct Input {
    static constexpr int kMaxThrottle = 15;
    static constexpr int kMaxSteer = 15;

    /// 0 (off) .. kMaxThrottle (full thrust).
    std::int8_t throttle = 0;
    /// -kMaxSteer (full left) .. +kMaxSteer (full right).
    std::int8_t steer = 0;
    /// 0 or 1.
    std::uint8_t brake = 0;

    /// Clamps every field into range (inputs read from outside go through this).
    static Input clamped(int throttle, int steer, int brake);
    /// 10 bits: throttle (4) | steer + 15 (5) << 4 | brake (1) << 9; Input{} packs to 240.
    std::uint16_t pack() const;
    /// Inverse of pack(); out-of-range fields are clamped.
    static Input unpack(std::uint16_t bits);
    bool operator==(const Input&) const = default;
};

/// best_gate_distance_m of a car that has not yet approached its next gate.
inline constexpr std::int32_t kFarFromGate_m = 1 << 30;

/// Everything that changes about a car from tick to tick. All of it is part
/// of the state hash and of snapshots.
struct CarState {
    /// Slot in use.
    bool active = false;
    /// Crossed the finish line on its last lap.
    bool finished = false;
    /// Centre of the sphere (unit: m).
    Vec3 position{0, 0, 0};
    /// (unit: m/s).
    Vec3 velocity{0, 0, 0};
    /// Local +Z is forward, +Y up. Components are quantised, so it is unit
    /// only to about 1e-4: use forward()/up(), which normalise.
    Quat orientation{1, 0, 0, 0};
    /// Gate to pass next (0 = start/finish line).
    std::int32_t next_checkpoint = 0;
    /// Current lap: 0 before the start line is first crossed.
    std::int32_t lap = 0;
    /// Last gate passed: where the car respawns.
    std::int32_t respawn_checkpoint = 0;
    /// Tick at which the car finished (valid when finished).
    std::uint32_t finish_tick = 0;
    /// Fraction [0,1) of that tick at which it crossed the line.
    double finish_fraction = 0;
    /// Times the car fell below the kill height or made no progress.
    std::uint32_t respawns = 0;
    /// Closest the car has come to its next gate, in whole metres (unit: m).
    std::int32_t best_gate_distance_m = kFarFromGate_m;
    /// Racing ticks since best_gate_distance_m last improved by 1 m.
    std::uint32_t no_progress_ticks = 0;

    [[gnu::always_inline]] Quat unit_orientation() const { return normalized_near_unit(orientation); }
    Vec3 forward() const { return axis_z(unit_orientation()); }
    Vec3 up() const { return axis_y(unit_orientation()); }
};

/// Puts a car at rest on a pose.
void place_car(CarState& car, const Pose& pose);

/// The orientation whose forward and up are the given (orthonormal) vectors.
Quat orientation_from(const Vec3& forward, const Vec3& up);

/// Phase 1, drive (per car, before integrate()): steering, thrust, brake,
/// gravity with the normal force of the supporting surface, drag and
/// sideways friction. Changes velocity and orientation, not position.
void apply_controls_and_forces(const PhysicsSettings& s, const Contacts& contacts, const Input& input, CarState& car);

/// What the controls and the alignment work out from a car's orientation
/// and its contacts, kept by the caller between steps; it never changes a
/// result. Three parts, each a function of its key alone:
/// - the unit orientation and its up, keyed by the bits of the orientation
///   as stored (a car that did not turn finds them again: both phases of its
///   step and the next steps read them without renormalising);
/// - the support frame: the contact normal closest to the car's up, and the
///   car's unit forward along that surface, keyed by that unit orientation
///   and the bits of the normal (a car going straight over one flat surface
///   reuses it);
/// - the sine and cosine of half the steering angle, keyed by the bits of
///   that angle (a steer held over several steps, as a hand or the AI holds
///   it, turns by the same angle each step).
struct SupportMemo {
    /// Key of the first part: the orientation as stored.
    Quat stored{0, 0, 0, 0};
    bool unit_valid = false;
    Quat unit{1, 0, 0, 0};
    Vec3 up{0, 1, 0};
    /// Key of the second part: the supporting normal; valid for `unit`.
    Vec3 normal{0, 1, 0};
    bool frame_valid = false;
    /// Supported, with a direction along the surface.
    bool grounded = false;
    /// Unit direction along the surface (valid when grounded).
    Vec3 forward{0, 0, 0};
    /// Key of the third part: the steering angle of one step (unit: rad).
    double turn_rad = 0;
    bool turn_valid = false;
    /// det_sin() and det_cos() of half of it.
    double turn_half_sin = 0;
    double turn_half_cos = 1;
};
/// The same, with the support frame kept in `memo` between calls.
void apply_controls_and_forces(const PhysicsSettings& s, const Contacts& contacts, const Input& input, CarState& car,
                               SupportMemo& memo);

/// The end of phase 1: moves the car by its velocity with the configured
/// integrator; `velocity_before` is its velocity before
/// apply_controls_and_forces() (Verlet and explicit Euler use it).
void integrate(const PhysicsSettings& s, const Vec3& velocity_before, CarState& car);

/// Phase 4 (after the push-out): turns the car's up towards the contact
/// normal closest to its current up.
void align_to_contacts(const PhysicsSettings& s, const Contacts& contacts, CarState& car);
/// The same, reading the unit orientation from `memo` if it holds this
/// car's (see SupportMemo; the controls keep it).
void align_to_contacts(const PhysicsSettings& s, const Contacts& contacts, CarState& car, const SupportMemo& memo);

/// Rounds position and velocity to the wire resolution.
void quantize_motion(CarState& car);
inline void quantize_motion(Vec3& position, Vec3& velocity) { quantize(position, kPosBits, velocity, kVelBits); }
/// Rounds the orientation to the wire resolution (w >= 0 representative).
void quantize_orientation(CarState& car);
/// Both.
inline void quantize_car(CarState& car) {
    quantize_motion(car);
    quantize_orientation(car);
}

}  // namespace jetrace
