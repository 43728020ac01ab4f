#include "jetrace/tracks/builtin_tracks.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace {

OvalParams stadium_params() { return OvalParams{}; }

OvalParams ring_params() {
    OvalParams p;
    p.name = "ring";
    p.straight_m = 120;
    p.turn_radius_m = 45;
    p.width_m = 30;
    p.floor_cell_m = 20;
    p.turn_segments = 12;
    p.wall = false;
    p.finish_line_m = 100;
    p.spawn_slots = 64;
    return p;
}

namespace {

constexpr double kCarRadius_m = 2.5;       // spawn heights assume the default car
constexpr double kRest_m = kCarRadius_m + 1.0 / 1024.0;

struct Sample {
    Vec3 pos;
    Vec3 heading;  // unit, horizontal
    bool gate;     // place a gate here
};

struct MeshBuilder {
    std::vector<Vec3> vertices;
    std::vector<std::uint32_t> indices;

    void quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
        const auto base = static_cast<std::uint32_t>(vertices.size());
        vertices.insert(vertices.end(), {a, b, c, d});
        indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
};

Vec3 lateral_of(const Vec3& heading) { return heading.cross(kWorldUp); }  // right-hand side

// Centre line of the oval, with gate flags.
std::vector<Sample> centre_line(const OvalParams& p) {
    std::vector<Sample> s;
    const double L = p.straight_m, R = p.turn_radius_m;
    const int straight_steps = std::max(1, static_cast<int>(std::ceil(L / 50.0)));
    const int half = p.turn_segments;
    // Straight A along +X at z = 0 (gates every 100 m until the wall or finish).
    for (int i = 0; i < straight_steps; ++i) {
        const double x = L * i / straight_steps;
        s.push_back({Vec3(x, 0, 0), Vec3(1, 0, 0), false});
    }
    // Turn 1 around (L, 0, R).
    for (int k = 0; k < half; ++k) {
        const double phi = kPi * k / half;
        s.push_back({Vec3(L + R * det_sin(phi), 0, R - R * det_cos(phi)), Vec3(det_cos(phi), 0, det_sin(phi)),
                     k > 0 && k % 2 == 0});
    }
    // Straight B along -X at z = 2R.
    for (int i = 0; i < straight_steps; ++i) {
        const double x = L - L * i / straight_steps;
        s.push_back({Vec3(x, 0, 2 * R), Vec3(-1, 0, 0), i > 0 && i % 4 == 0});
    }
    // Turn 2 around (0, 0, R).
    for (int k = 0; k < half; ++k) {
        const double phi = kPi * k / half;
        s.push_back({Vec3(-R * det_sin(phi), 0, R + R * det_cos(phi)), Vec3(-det_cos(phi), 0, -det_sin(phi)),
                     k % 2 == 0});
    }
    return s;
}

// Position and heading at arc length `d` along the closed centre line.
Sample along(const std::vector<Sample>& line, double d) {
    std::vector<double> cum(line.size() + 1, 0.0);
    for (std::size_t i = 0; i < line.size(); ++i) {
        cum[i + 1] = cum[i] + (line[(i + 1) % line.size()].pos - line[i].pos).norm();
    }
    const double total = cum.back();
    d = d - std::floor(d / total) * total;
    for (std::size_t i = 0; i < line.size(); ++i) {
        if (d <= cum[i + 1]) {
            const Vec3& a = line[i].pos;
            const Vec3& b = line[(i + 1) % line.size()].pos;
            const double f = (d - cum[i]) / (cum[i + 1] - cum[i]);
            return {a + (b - a) * f, (b - a).normalized(), false};
        }
    }
    return line.front();
}

Checkpoint floor_gate(const Vec3& at, const Vec3& heading, double half_width, double center_y, double half_height) {
    Checkpoint c;
    c.center = Vec3(at.x(), center_y, at.z());
    c.normal = heading;
    c.up = kWorldUp;
    c.across = heading.cross(kWorldUp);
    c.half_width_m = half_width;
    c.half_height_m = half_height;
    c.respawn = {Vec3(at.x(), kRest_m, at.z()), heading, kWorldUp};
    return c;
}

void add_barriers(const OvalParams& p, const std::vector<Sample>& line, MeshBuilder& m) {
    const double hw = p.width_m / 2;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const Sample& a = line[i];
        const Sample& b = line[(i + 1) % line.size()];
        // Offsets use each end's own lateral so the turns' barriers join up.
        for (double side : {-1.0, 1.0}) {
            const Vec3 pa = a.pos + lateral_of(a.heading) * (side * hw);
            const Vec3 pb = b.pos + lateral_of(b.heading) * (side * hw);
            const Vec3 h(0, p.barrier_height_m, 0);
            m.quad(pa, pb, pb + h, pa + h);
        }
    }
}

void add_floor_and_walls(const OvalParams& p, MeshBuilder& m) {
    const double margin = p.width_m;
    const double x0 = -p.turn_radius_m - margin, x1 = p.straight_m + p.turn_radius_m + margin;
    const double z0 = -margin, z1 = 2 * p.turn_radius_m + margin;
    const int nx = std::max(1, static_cast<int>(std::ceil((x1 - x0) / p.floor_cell_m)));
    const int nz = std::max(1, static_cast<int>(std::ceil((z1 - z0) / p.floor_cell_m)));
    for (int j = 0; j < nz; ++j) {
        for (int i = 0; i < nx; ++i) {
            const double xa = x0 + (x1 - x0) * i / nx, xb = x0 + (x1 - x0) * (i + 1) / nx;
            const double za = z0 + (z1 - z0) * j / nz, zb = z0 + (z1 - z0) * (j + 1) / nz;
            // Counter-clockwise seen from above: normal +Y.
            m.quad(Vec3(xa, 0, za), Vec3(xa, 0, zb), Vec3(xb, 0, zb), Vec3(xb, 0, za));
        }
    }
    const double h = 30;
    const Vec3 c00(x0, 0, z0), c10(x1, 0, z0), c11(x1, 0, z1), c01(x0, 0, z1), up(0, h, 0);
    m.quad(c00, c10, c10 + up, c00 + up);
    m.quad(c10, c11, c11 + up, c10 + up);
    m.quad(c11, c01, c01 + up, c11 + up);
    m.quad(c01, c00, c00 + up, c01 + up);
}

// The quarter-pipe and the 85 degree wall across the first straight.
// Returns the gate at its top.
Checkpoint add_wall(const OvalParams& p, MeshBuilder& m) {
    const double hw = p.width_m / 2;
    const double alpha = p.wall_angle_deg * kPi / 180.0;
    const double Rq = p.wall_curve_radius_m;
    const int pipe_segments = 12;
    std::vector<Vec3> profile;  // (x, y) in the plane z = 0
    for (int k = 0; k <= pipe_segments; ++k) {
        const double th = alpha * k / pipe_segments;
        profile.emplace_back(p.wall_start_m + Rq * det_sin(th), Rq - Rq * det_cos(th), 0);
    }
    const Vec3 dir(det_cos(alpha), det_sin(alpha), 0);
    const Vec3 base = profile.back();
    const int wall_segments = 10;
    for (int k = 1; k <= wall_segments; ++k) profile.push_back(base + dir * (p.wall_length_m * k / wall_segments));
    const Vec3 zl(0, 0, -hw), zr(0, 0, hw);
    for (std::size_t k = 0; k + 1 < profile.size(); ++k) {
        m.quad(profile[k] + zr, profile[k + 1] + zr, profile[k + 1] + zl, profile[k] + zl);
    }
    const Vec3 normal(-det_sin(alpha), det_cos(alpha), 0);  // faces the oncoming car
    const Vec3 at = base + dir * (p.wall_length_m - 30.0);
    Checkpoint c;
    c.center = at + normal * (kCarRadius_m + 5.0);
    c.normal = dir;
    c.up = normal;
    c.across = dir.cross(normal);
    c.half_width_m = hw + 2;
    c.half_height_m = 15;
    c.respawn = {at + normal * kRest_m, dir, normal};
    return c;
}

}  // namespace

Track make_oval(const OvalParams& p) {
    MeshBuilder m;
    const std::vector<Sample> line = centre_line(p);
    add_floor_and_walls(p, m);
    add_barriers(p, line, m);

    const double hw = p.width_m / 2 + 2;
    std::vector<Checkpoint> gates;
    // Gate 0: start/finish. With the wall, tall enough to catch a car still
    // falling from it.
    const double top = p.wall ? p.wall_length_m + p.wall_curve_radius_m + 1500 : 30;
    gates.push_back(floor_gate(Vec3(p.finish_line_m, 0, 0), Vec3(1, 0, 0), hw, top - 10, top));
    // Gates along the rest of the lap, in driving order from the finish line.
    for (const Sample& s : line) {
        if (s.gate) gates.push_back(floor_gate(s.pos, s.heading, hw, 10, 30));
    }
    const double first_straight_end = p.wall ? p.wall_start_m - 20 : p.finish_line_m - 20;
    for (double x = 100; x < first_straight_end; x += 100) {
        gates.push_back(floor_gate(Vec3(x, 0, 0), Vec3(1, 0, 0), hw, 10, 30));
    }
    if (p.wall) gates.push_back(add_wall(p, m));

    // Spawn grid: 4 columns, rows every 12 m behind the line along the centre line.
    std::vector<Pose> spawns;
    double finish_arc = p.finish_line_m;  // straight A starts at arc length 0
    for (int i = 0; i < p.spawn_slots; ++i) {
        const int row = i / 4, col = i % 4;
        const Sample s = along(line, finish_arc - 15.0 - 12.0 * row);
        const double offset = -p.width_m / 2 + p.width_m / 8 * (2 * col + 1);
        const Vec3 pos = s.pos + lateral_of(s.heading) * offset;
        spawns.push_back({Vec3(pos.x(), kRest_m, pos.z()), s.heading, kWorldUp});
    }
    return make_track(p.name, m.vertices, m.indices, std::move(gates), std::move(spawns), -50.0);
}

std::vector<std::string> builtin_track_names() { return {"stadium", "ring"}; }

bool make_builtin_track(const std::string& name, Track& out) {
    if (name == "stadium") {
        out = make_oval(stadium_params());
        return true;
    }
    if (name == "ring") {
        out = make_oval(ring_params());
        return true;
    }
    return false;
}

bool load_builtin(const std::string& spec, Track& out, std::string& error) {
    if (make_builtin_track(spec, out)) return true;
    error = "unknown built-in track '" + spec + "'";
    return false;
}

}  // namespace jetrace
