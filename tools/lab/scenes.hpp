// Scenes for the speed-against-accuracy study and the failure-mode tests
// (issue 4): small synthetic tracks, the stadium at any tessellation, and a
// switch for the collision mode. Shared by jetrace-bench and the tests so a
// scenario is written once.
#pragma once

#include "jetrace/core/world.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include <algorithm>
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

    /// One quad each: the floor y = 0 over [-half_m, half_m]^2; a wall in the
    /// plane x = x0 (normal -X) or z = z0 (normal -Z), y in [0, height_m],
    /// the other coordinate in [-half_m, half_m].
    void floor(double half_m) { floor(-half_m, half_m, -half_m, half_m, 2 * half_m); }
    void wall_x(double x0, double height_m, double half_m) { wall_x(x0, height_m, half_m, std::max(height_m, 2 * half_m)); }
    void wall_z(double z0, double height_m, double half_m) {
        quad(Vec3(-half_m, 0, z0), Vec3(-half_m, height_m, z0), Vec3(half_m, height_m, z0), Vec3(half_m, 0, z0));
    }
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

/// Sets the collision mode: the swept test before the push-out, or the
/// seed's discrete push-out alone.
inline void set_swept(PhysicsSettings& s, bool swept) {
    s.collision_mode = swept ? CollisionMode::swept : CollisionMode::discrete;
}

/// "swept" or "discrete".
inline const char* mode_name(const PhysicsSettings& s) { return to_string(s.collision_mode); }

// ------------------------------------------------------------------ tracks

/// The stadium with its floor split into squares of `floor_cell_m` (35 m is
/// the built-in stadium, 1,384 triangles; 1.15 m gives about 1,000,000).
Track refined_stadium(double floor_cell_m);

/// `n` x `n` copies of the built-in stadium side by side, 2 km apart (a large
/// synthetic track at the stadium's density); gates and spawns of copy 0.
Track tiled_stadium(int n);

}  // namespace jetrace::lab
