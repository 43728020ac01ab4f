#include "lab/scenes.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace jetrace::lab {

void Mesh::quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const auto base = static_cast<std::uint32_t>(vertices.size());
    vertices.insert(vertices.end(), {a, b, c, d});
    indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

namespace {
int cells(double extent, double cell) { return std::max(1, static_cast<int>(std::ceil(extent / cell - 1e-9))); }
}  // namespace

void Mesh::floor(double x0, double x1, double z0, double z1, double cell_m) {
    const int nx = cells(x1 - x0, cell_m), nz = cells(z1 - z0, cell_m);
    for (int j = 0; j < nz; ++j) {
        for (int i = 0; i < nx; ++i) {
            const double xa = x0 + (x1 - x0) * i / nx, xb = x0 + (x1 - x0) * (i + 1) / nx;
            const double za = z0 + (z1 - z0) * j / nz, zb = z0 + (z1 - z0) * (j + 1) / nz;
            quad(Vec3(xa, 0, za), Vec3(xa, 0, zb), Vec3(xb, 0, zb), Vec3(xb, 0, za));
        }
    }
}

void Mesh::wall_x(double x0, double height_m, double half_m, double cell_m) {
    const int ny = cells(height_m, cell_m), nz = cells(2 * half_m, cell_m);
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nz; ++i) {
            const double za = -half_m + 2 * half_m * i / nz, zb = -half_m + 2 * half_m * (i + 1) / nz;
            const double ya = height_m * j / ny, yb = height_m * (j + 1) / ny;
            quad(Vec3(x0, ya, za), Vec3(x0, ya, zb), Vec3(x0, yb, zb), Vec3(x0, yb, za));
        }
    }
}

PhysicsSettings lab_physics() {
    PhysicsSettings ps;
    ps.no_progress_s = 3599.0;
    return ps;
}

Scene make_lab_scene(const Mesh& mesh, const PhysicsSettings& physics, double cell_size_m) {
    assert(validate(physics).empty());
    const double rest = physics.car_radius_m + physics.resolver_epsilon_m;
    const Pose spawn{Vec3(0, rest, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    Checkpoint g0;
    g0.center = Vec3(0, 10, 1.0e5);
    g0.normal = Vec3(0, 0, 1);
    g0.across = Vec3(-1, 0, 0);
    g0.up = Vec3(0, 1, 0);
    g0.respawn = spawn;
    Checkpoint g1 = g0;
    g1.center = Vec3(0, 10, -1.0e5);
    g1.normal = Vec3(0, 0, -1);
    g1.across = Vec3(1, 0, 0);
    Track track = make_track("lab", mesh.vertices, mesh.indices, {g0, g1}, {spawn}, -1.0e5);
    return Scene::make(std::move(track), physics, cell_size_m);
}

WorldState one_car(const Vec3& position, const Vec3& forward, const Vec3& velocity) {
    WorldState st = make_world(1, 1);
    CarState& car = st.cars[0];
    car.active = true;
    place_car(car, Pose{position, forward, Vec3(0, 1, 0)});
    car.velocity = velocity;
    quantize_motion(car);
    return st;
}

double min_distance(const Track& track, const Vec3& p) {
    double d2 = 1e300;
    for (const Triangle& t : track.triangles) d2 = std::min(d2, (p - closest_point_on_triangle(p, t).point).squaredNorm());
    return std::sqrt(d2);
}

Track refined_stadium(double floor_cell_m) {
    OvalParams p = stadium_params();
    p.floor_cell_m = floor_cell_m;
    return make_oval(p);
}

Track tiled_stadium(int n) {
    const Track one = make_oval(stadium_params());
    Mesh m;
    const double pitch_x = 2000.0, pitch_z = 800.0;  // the stadium is 1,730 m x 380 m
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const Vec3 off(pitch_x * i, 0, pitch_z * j);
            for (const Triangle& t : one.triangles) {
                const auto base = static_cast<std::uint32_t>(m.vertices.size());
                m.vertices.insert(m.vertices.end(), {t.a + off, t.b + off, t.c + off});
                m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
            }
        }
    }
    return make_track("stadium-tiled", m.vertices, m.indices, one.checkpoints, one.spawns, one.kill_height_m);
}

}  // namespace jetrace::lab
