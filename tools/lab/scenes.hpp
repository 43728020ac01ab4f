// Scenes for the speed-against-accuracy study and the failure-mode tests
// (issue 4): small synthetic tracks, the stadium at any tessellation, and a
// switch for the collision mode. Shared by jetrace-bench and the tests so a
// scenario is written once.
#pragma once

#include "jetrace/builtin_tracks.hpp"
#include "jetrace/world.hpp"

#include <cstdint>
#include <vector>

namespace jetrace::lab {

/// An indexed triangle mesh under construction.
struct Mesh {
    std::vector<Vec3> vertices;
    std::vector<std::uint32_t> indices;

    /// Two triangles (a, b, c) and (a, c, d); normal by the right-hand rule.
    void quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
    /// The floor y = 0 over x in [x0, x1], z in [z0, z1], split into squares
    /// of about `cell_m` (normal +Y).
    void floor(double x0, double x1, double z0, double z1, double cell_m);
    /// A zero-thickness wall in the plane x = x0, y in [0, height_m], z in
    /// [-half_m, half_m], split into squares of about `cell_m` (normal -X).
    void wall_x(double x0, double height_m, double half_m, double cell_m);
};

/// Physics for the custom scenes: the defaults, except that a car is never
/// respawned for lack of progress.
PhysicsSettings lab_physics();

/// A scene from `mesh` with two gates far away (rules run but never fire),
/// one spawn resting on y = 0 at the origin facing +X, and a kill height far
/// below. `physics` must be valid.
Scene make_lab_scene(const Mesh& mesh, const PhysicsSettings& physics, double cell_size_m = 0.0);

/// A one-car world with the car at rest at `position` facing `forward` (up
/// +Y), then given `velocity`; quantised like the state.
WorldState one_car(const Vec3& position, const Vec3& forward, const Vec3& velocity);

/// Smallest distance from `p` to any triangle of `track` (brute force).
double min_distance(const Track& track, const Vec3& p);

// ------------------------------------------------------------ collision mode

/// True once the core has PhysicsSettings::collision_mode (the lead's swept
/// mode); until then only the discrete push-out exists.
template <class S>
concept HasCollisionMode = requires(S s) { s.collision_mode; };

inline constexpr bool kSweptAvailable = HasCollisionMode<PhysicsSettings>;

/// Sets the collision mode when the core has one (no-op for discrete
/// otherwise). Returns false if `swept` was asked for but does not exist.
template <class S = PhysicsSettings>
bool set_swept(S& s, bool swept) {
    if constexpr (HasCollisionMode<S>) {
        using Mode = decltype(s.collision_mode);
        s.collision_mode = swept ? Mode::swept : Mode::discrete;
        return true;
    } else {
        return !swept;
    }
}

/// "swept" or "discrete" for the settings' mode ("discrete" before the mode exists).
template <class S = PhysicsSettings>
const char* mode_name(const S& s) {
    if constexpr (HasCollisionMode<S>) {
        using Mode = decltype(s.collision_mode);
        return s.collision_mode == Mode::swept ? "swept" : "discrete";
    } else {
        (void)s;
        return "discrete";
    }
}

// ------------------------------------------------------------------ tracks

/// The stadium with its floor split into squares of `floor_cell_m` (35 m is
/// the built-in stadium, 1,384 triangles; 1.15 m gives about 1,000,000).
Track refined_stadium(double floor_cell_m);

/// `n` x `n` copies of the built-in stadium side by side, 2 km apart (a large
/// synthetic track at the stadium's density); gates and spawns of copy 0.
Track tiled_stadium(int n);

}  // namespace jetrace::lab
