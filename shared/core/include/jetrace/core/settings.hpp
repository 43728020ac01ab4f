// Plain settings structs with defaults and a unit on every field.
// Validated once, where they enter the program (see validate()).
#pragma once

#include <cstdint>
#include <string>

namespace jetrace {

enum class Integrator : std::uint8_t {
    /// x += v*dt, then v += a*dt (the seed's method).
    explicit_euler = 0,
    /// v += a*dt, then x += v*dt (symplectic).
    semi_implicit_euler = 1,
    /// v += a*dt, then x += (v_old + v_new)*dt/2: velocity Verlet with the
    /// acceleration evaluated once per step; exact for constant acceleration.
    /// The default: `jetrace-bench integrators` measures 25 times less error
    /// than either Euler at 120 Hz (docs/PERFORMANCE.md).
    velocity_verlet = 2,
};

const char* to_string(Integrator i);

enum class CollisionMode : std::uint8_t {
    /// The seed's method: push the car out of wherever the step ends. A car
    /// moving more than about its radius per step can pass a thin wall.
    discrete = 0,
    /// Sweep the sphere along the step's motion first (first contact, slide
    /// along), then push out: no pass-through at any speed the step rate
    /// can carry (docs/ACCURACY.md). Costs nothing for a car moving less
    /// than half its radius per step (unit: none). The default.
    swept = 1,
};

const char* to_string(CollisionMode m);

enum class PushOut : std::uint8_t {
    /// The seed's resolver: a pass pushes the car out of the first triangle
    /// it touches (in triangle order) and ends. Where many triangles meet (a
    /// corner fanned into thin triangles) 20 passes can run out with the car
    /// still inside; with epsilon 0 one triangle eats every pass.
    first_contact = 0,
    /// A pass pushes the car out of every triangle it touches, in triangle
    /// order, each at the position the previous push left (Gauss-Seidel).
    /// The default: a corner that needs about 50 first-contact passes needs
    /// 3 of these (docs/ACCURACY.md).
    each_contact = 1,
};

const char* to_string(PushOut p);

struct PhysicsSettings {
    /// Fixed steps per simulated second (unit: Hz).
    int tick_rate_hz = 120;
    /// Downward gravitational acceleration (unit: m/s^2).
    double gravity_mps2 = 9.81;
    /// Radius of a car's collision sphere (unit: m). The seed's car is 5 m across.
    double car_radius_m = 2.5;
    /// Acceleration from full throttle while in contact with the track (unit: m/s^2).
    double thrust_mps2 = 24.0;
    /// Quadratic air drag: deceleration = drag * speed^2 (unit: 1/m). With the
    /// default thrust the flat top speed is sqrt(24/1.8e-4) = 365 m/s, the
    /// seed's "3 m per frame".
    double drag_per_m = 1.8e-4;
    /// Deceleration from the brake while in contact (unit: m/s^2).
    double brake_mps2 = 30.0;
    /// Yaw rate at full steering lock (unit: rad/s).
    double steer_rate_radps = 1.6;
    /// Static sideways friction: sideways speed below grip_mps2*dt is removed
    /// in one step (grip) (unit: m/s^2).
    double grip_mps2 = 40.0;
    /// Kinetic sideways friction: above the grip threshold, sideways speed only
    /// decreases by slide_mps2*dt per step (drift). Must be below grip_mps2
    /// (unit: m/s^2).
    double slide_mps2 = 15.0;
    /// Fraction of the remaining angle between the car's up and the chosen
    /// contact normal closed per second (unit: 1/s); capped at one step's worth.
    double align_rate_per_s = 12.0;
    /// A contact supports the car (thrust, grip, alignment) only if its normal
    /// is within this cosine of the car's up or of world up: the car rides
    /// gradual curves up to the 85 degree wall, and lands on floors from any
    /// attitude, but a barrier hit from the side stays an obstacle
    /// (unit: cosine; 0.5 = 60 degrees).
    double ride_min_cos = 0.5;
    /// A racing car that has not come at least 1 m closer to its next gate
    /// for this long respawns at its last gate: stuck, lost or off the track
    /// (unit: s).
    double no_progress_s = 10.0;
    /// Maximum push-out passes against the track per step (unit: passes).
    int resolver_passes = 20;
    /// What one pass does (see PushOut).
    PushOut push_out = PushOut::each_contact;
    /// Extra distance a penetrating car is pushed beyond touching (unit: m).
    double resolver_epsilon_m = 1.0 / 1024.0;
    /// A triangle closer than radius + skin counts as a contact for friction,
    /// thrust and alignment (unit: m). Must exceed resolver_epsilon_m.
    double contact_skin_m = 0.05;
    /// Discrete push-out only, or a swept test first: see CollisionMode.
    CollisionMode collision_mode = CollisionMode::swept;
    /// Most slides along surfaces in one step of the swept test (unit: contacts).
    int sweep_contacts = 4;
    /// How the car moves between positions: see Integrator.
    Integrator integrator = Integrator::velocity_verlet;
    /// Round positions and velocities to 2^-quant_bits after every step so
    /// snapshots carry the state exactly (unit: flag).
    bool quantize_state = true;

    double dt_s() const { return 1.0 / tick_rate_hz; }
};

/// Returns an empty string if the settings are usable, else what is wrong.
std::string validate(const PhysicsSettings& s);

/// Revision of what step() computes from the same settings and state: it
/// changes with any change that alters a result (the golden hash in
/// tests/core/test_determinism.cpp moves with it), and only then. It is the
/// first value physics_fingerprint() hashes, so peers running different
/// cores refuse each other instead of diverging: the Welcome carries the
/// fingerprint as physics_hash (docs/PROTOCOL.md, "Hashes"), and a replay's
/// header carries it too, so that a replay recorded by another core fails
/// verification as "physics", not as a desync at some tick.
inline constexpr std::uint32_t kPhysicsRevision = 3;

/// Hash of kPhysicsRevision and every field (raw bits): peers and replays
/// must agree on it.
std::uint64_t physics_fingerprint(const PhysicsSettings& s);

/// Quantisation of the simulated state (also the wire format's resolution).
/// Positions and velocities: 2^-10 m and 2^-10 m/s. Quaternion components: 2^-14.
inline constexpr int kPosBits = 10;
inline constexpr int kVelBits = 10;
inline constexpr int kQuatBits = 14;

}  // namespace jetrace
