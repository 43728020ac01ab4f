#include "jetrace/core/track.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace jetrace {

double distance_to_gate(const Checkpoint& g, const Vec3& p) { return std::sqrt(squared_distance_to_gate(g, p)); }

std::uint64_t Track::identity() const {
    Fnv1a h;
    h.u64(triangles.size());
    for (const Triangle& t : triangles) {
        h.vec3(t.a);
        h.vec3(t.b);
        h.vec3(t.c);
    }
    h.u64(checkpoints.size());
    for (const Checkpoint& c : checkpoints) {
        h.vec3(c.center);
        h.vec3(c.normal);
        h.vec3(c.across);
        h.vec3(c.up);
        h.f64(c.half_width_m);
        h.f64(c.half_height_m);
        h.vec3(c.respawn.position);
        h.vec3(c.respawn.forward);
        h.vec3(c.respawn.up);
    }
    h.u64(spawns.size());
    for (const Pose& p : spawns) {
        h.vec3(p.position);
        h.vec3(p.forward);
        h.vec3(p.up);
    }
    h.f64(kill_height_m);
    return h.value();
}

void add_triangle(Track& t, const Vec3& a, const Vec3& b, const Vec3& c) {
    t.triangles.push_back(Triangle::make(a, b, c));
    const Triangle& tri = t.triangles.back();
    if (t.triangles.size() == 1) t.bounds = tri.bounds();
    t.bounds.expand(tri.a);
    t.bounds.expand(tri.b);
    t.bounds.expand(tri.c);
}

Track make_track(std::string name, const std::vector<Vec3>& vertices, const std::vector<std::uint32_t>& indices,
                 std::vector<Checkpoint> checkpoints, std::vector<Pose> spawns, double kill_height_m) {
    Track t;
    t.name = std::move(name);
    t.triangles.reserve(indices.size() / 3);
    for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
        add_triangle(t, vertices[indices[i]], vertices[indices[i + 1]], vertices[indices[i + 2]]);
    }
    t.checkpoints = std::move(checkpoints);
    t.spawns = std::move(spawns);
    t.kill_height_m = kill_height_m;
    return t;
}

namespace {

bool finite_in_range(const Vec3& v) {
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(v[i]) || std::abs(v[i]) > kMaxTrackCoordinate_m) return false;
    }
    return true;
}

bool unit(const Vec3& v) { return finite_in_range(v) && std::abs(v.squaredNorm() - 1.0) < 1e-6; }

bool valid_pose(const Pose& p) {
    return finite_in_range(p.position) && unit(p.forward) && unit(p.up) && std::abs(p.forward.dot(p.up)) < 1e-6;
}

}  // namespace

std::string validate(const Track& track) {
    std::ostringstream err;
    if (track.triangles.empty()) return "track has no triangles";
    if (track.triangles.size() > kMaxTrackTriangles) {
        err << "track has " << track.triangles.size() << " triangles; at most " << kMaxTrackTriangles << " are allowed";
        return err.str();
    }
    for (std::size_t i = 0; i < track.triangles.size(); ++i) {
        const Triangle& t = track.triangles[i];
        if (!finite_in_range(t.a) || !finite_in_range(t.b) || !finite_in_range(t.c)) {
            err << "triangle " << i << " has a coordinate that is not finite or exceeds " << kMaxTrackCoordinate_m << " m";
            return err.str();
        }
    }
    return validate_rules(track);
}

std::string validate_rules(const Track& track) {
    std::ostringstream err;
    if (track.checkpoints.size() < 2) return "track needs at least 2 checkpoints (start/finish and one more)";
    for (std::size_t i = 0; i < track.checkpoints.size(); ++i) {
        const Checkpoint& c = track.checkpoints[i];
        if (!finite_in_range(c.center) || !unit(c.normal) || !unit(c.across) || !unit(c.up) ||
            std::abs(c.normal.dot(c.across)) > 1e-6 || std::abs(c.normal.dot(c.up)) > 1e-6 ||
            std::abs(c.across.dot(c.up)) > 1e-6) {
            err << "checkpoint " << i << " has a bad frame (needs finite centre and orthonormal normal/across/up)";
            return err.str();
        }
        if (!(c.half_width_m > 0 && c.half_width_m < 1e5 && c.half_height_m > 0 && c.half_height_m < 1e5)) {
            err << "checkpoint " << i << " has half extents outside (0, 1e5) m";
            return err.str();
        }
        if (!valid_pose(c.respawn)) {
            err << "checkpoint " << i << " has a bad respawn pose";
            return err.str();
        }
    }
    if (track.spawns.empty()) return "track has no spawn slots";
    for (std::size_t i = 0; i < track.spawns.size(); ++i) {
        if (!valid_pose(track.spawns[i])) {
            err << "spawn " << i << " has a bad pose (finite position, unit orthogonal forward and up)";
            return err.str();
        }
        if (!(track.spawns[i].position.y() > track.kill_height_m)) {
            err << "spawn " << i << " is below the kill height";
            return err.str();
        }
    }
    if (!std::isfinite(track.kill_height_m)) return "kill height is not finite";
    return {};
}

}  // namespace jetrace
