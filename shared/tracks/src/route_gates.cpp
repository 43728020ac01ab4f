// Gates and spawns from a manifest's route (or its explicit gates), placed on
// the mesh by casting rays: down to find the road, up to find the clearance,
// sideways to find the road's width. docs/TRACKS.md, "Route, gates, spawns".
#include "route_gates.hpp"

#include "route_line.hpp"
#include "track_raycast.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace jetrace::detail {

const std::string& Surface::part_of(std::size_t tri) const {
    const auto it = std::upper_bound(parts.begin(), parts.end(), tri,
                                     [](std::size_t t, const auto& p) { return t < p.first; });
    static const std::string none = "?";
    return it == parts.end() ? none : it->second;
}

std::string where(const Vec3& p) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.1f, %.1f, %.1f)", p.x(), p.y(), p.z());
    return buf;
}

namespace {

bool fail(std::string& error, std::string message) {
    error = std::move(message);
    return false;
}

std::string metres(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f m", x);
    return buf;
}

std::string where_xz(const RoutePoint& p) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "(x %.1f, z %.1f)", p.x, p.z);
    return buf;
}

struct Ground {
    Vec3 point{0, 0, 0};
    std::size_t tri = 0;
};

// The lowest surface on the vertical line through p (normals are not trusted:
// exports wind faces either way), or the top of a stack of surfaces less than
// 0.25 m apart there (a road laid on terrain, a decal on a floor).
bool lowest_floor(const Surface& s, const RoutePoint& p, Ground& g) {
    constexpr double kLayer_m = 0.25, kStep_m = 1e-3;
    double t = 0;
    const Vec3 below(p.x, s.bounds.min.y() - 1.0, p.z);
    if (!raycast_index(s.tris, below, kWorldUp, t, g.tri)) return false;
    g.point = below + kWorldUp * t;
    std::size_t next = 0;
    for (int i = 0; i < 256; ++i) {
        if (!raycast_index(s.tris, g.point + kWorldUp * kStep_m, kWorldUp, t, next) || t + kStep_m > kLayer_m) break;
        g.point += kWorldUp * (t + kStep_m);
        g.tri = next;
    }
    return true;
}

// The road under a route point: below its y when it has one, else the
// lowest (or highest) surface on the vertical line through it.
bool ground_at(const Surface& s, const RoutePoint& p, Ground& g) {
    double t = 0;
    Vec3 o(p.x, 0, p.z);
    if (p.y) {
        o.y() = *p.y + kRest_m;
    } else if (s.mode == RouteSurface::highest) {
        o.y() = s.bounds.max.y() + 1.0;
    } else {
        return lowest_floor(s, p, g);
    }
    if (!raycast_index(s.tris, o, -kWorldUp, t, g.tri)) return false;
    g.point = o - kWorldUp * t;
    return true;
}

// Free height above a road point (infinite under open sky) and what bounds it.
double clearance(const Surface& s, const Vec3& road, std::size_t& over) {
    constexpr double kLift = 0.05;  // skips coplanar overlays (decals, doubled faces)
    double t = 0;
    if (!raycast_index(s.tris, road + kWorldUp * kLift, kWorldUp, t, over)) return std::numeric_limits<double>::infinity();
    return t + kLift;
}

// Distance to a wall along `dir` from the car's centre height, at most `cap`.
double free_side(const Surface& s, const Vec3& road, const Vec3& dir, double cap) {
    double t = 0;
    std::size_t tri = 0;
    if (raycast_index(s.tris, road + kWorldUp * kRest_m, dir, t, tri) && t < cap) return t;
    return cap;
}

bool make_gate(const Surface& s, std::size_t i, const ManifestGate& spec, const Vec3& dir, const TrackManifest& m,
               Checkpoint& c, std::string& error) {
    const std::string name = "gate " + std::to_string(i);
    Ground g;
    if (!ground_at(s, spec.position, g)) {
        return fail(error, name + " at " + where_xz(spec.position) + " has no drivable surface under its centre");
    }
    std::size_t over = 0;
    const double room = clearance(s, g.point, over);
    if (room < kCarHeight_m) {
        return fail(error, name + " at " + where(g.point) + ": '" + s.part_of(over) + "' is " + metres(room) +
                               " above the road (a roof, gantry or bridge); a car needs " + metres(kCarHeight_m));
    }
    c.normal = dir;
    c.up = kWorldUp;
    c.across = c.normal.cross(c.up);
    Vec3 base = g.point;
    if (spec.width_m > 0) {
        c.half_width_m = spec.width_m / 2;
    } else {  // centred between the walls the side rays find
        const double cap = m.gate_width_m / 2;
        const double left = free_side(s, g.point, -c.across, cap), right = free_side(s, g.point, c.across, cap);
        base += c.across * ((right - left) / 2);
        c.half_width_m = std::max((left + right) / 2, kRest_m);
    }
    const double height = spec.height_m > 0 ? spec.height_m : std::min(room, m.gate_height_m);
    c.half_height_m = height / 2;
    c.center = base + c.up * c.half_height_m;
    if (rest_on_surface(s.tris, c.center, -c.up, c.normal, c.respawn) != Rest::ok) {
        return fail(error, name + " at " + where(c.center) + " has no drivable surface under its centre");
    }
    return true;
}

bool route_gates(const TrackManifest& m, const Surface& s, const RouteLine& r, Track& t, std::string& error) {
    const double count = std::max(2.0, std::round(r.length() / m.gate_spacing_m));
    if (count > 10000) {
        return fail(error, "the route is " + metres(r.length()) + " long: more than 10000 gates at 'gate_spacing_m' " +
                               metres(m.gate_spacing_m));
    }
    const auto k = static_cast<std::size_t>(count);
    for (std::size_t i = 0; i < k; ++i) {
        ManifestGate spec;
        Vec3 dir;
        r.at(r.length() * static_cast<double>(i) / static_cast<double>(k), spec.position, dir);
        if (!make_gate(s, i, spec, dir, m, t.checkpoints.emplace_back(), error)) return false;
    }
    return true;
}

// Explicit gates: each must face along the route and follow its order.
bool explicit_gates(const TrackManifest& m, const Surface& s, const RouteLine* r, Track& t, double& start_u,
                    std::string& error) {
    double first = 0, previous = -1;
    for (std::size_t i = 0; i < m.gates.size(); ++i) {
        const ManifestGate& g = m.gates[i];
        const std::string name = "gate " + std::to_string(i) + " at " + where_xz(g.position);
        Vec3 dir = g.direction.value_or(Vec3::Zero());
        if (r) {
            Vec3 tangent;
            const double u = r->project(g.position, tangent);
            if (!g.direction) dir = tangent;
            const double angle = std::acos(std::clamp(dir.dot(tangent), -1.0, 1.0)) * 180.0 / kPi;
            if (angle > 90.0) {
                return fail(error, name + " is wound against the route: its direction is " +
                                       std::to_string(static_cast<int>(std::lround(angle))) + " degrees from the route's");
            }
            if (i == 0) first = u;
            const double along = std::fmod(u - first + r->length(), r->length());
            if (i > 0 && !(along > previous)) {
                return fail(error, name + " is out of order: it lies " + metres(along) + " along the route from gate 0, "
                                       "gate " + std::to_string(i - 1) + " at " + metres(previous));
            }
            previous = along;
        }
        if (!make_gate(s, i, g, dir, m, t.checkpoints.emplace_back(), error)) return false;
    }
    start_u = first;
    return true;
}

bool make_spawns(const TrackManifest& m, const Surface& s, const RouteLine* r, double start_u, Track& t,
                 std::string& error) {
    const Checkpoint& g0 = t.checkpoints[0];
    const int columns = m.spawn_column_spacing_m > 0 ? 2 : 1;
    for (int i = 0; i < m.spawn_count; ++i) {
        const double back = m.spawn_back_m + (i / columns) * m.spawn_row_spacing_m;
        const double side = columns == 1 ? 0.0 : ((i % columns) == 0 ? -0.5 : 0.5) * m.spawn_column_spacing_m;
        RoutePoint p;
        Vec3 dir = g0.normal;
        if (r) {
            r->at(start_u - back, p, dir);
        } else {
            const Vec3 q = g0.respawn.position - dir * back;
            p = {q.x(), q.z(), q.y()};
        }
        const Vec3 across = dir.cross(kWorldUp);
        p.x += across.x() * side;
        p.z += across.z() * side;
        const std::string name = "spawn " + std::to_string(i) + " at " + where_xz(p);
        Ground g;
        if (!ground_at(s, p, g)) return fail(error, name + " has no drivable surface under it");
        std::size_t over = 0;
        const double room = clearance(s, g.point, over);
        if (room < kCarHeight_m) {
            return fail(error, name + ": '" + s.part_of(over) + "' is " + metres(room) + " above the road; a car needs " +
                                   metres(kCarHeight_m));
        }
        if (rest_on_surface(s.tris, g.point + kWorldUp * kRest_m, -kWorldUp, dir, t.spawns.emplace_back()) != Rest::ok) {
            return fail(error, name + " has no drivable surface under it");
        }
    }
    return true;
}


constexpr std::size_t kMaxWarnings = 20;

void warn(TrackReport& report, std::string message) {
    if (report.warnings.size() < kMaxWarnings) report.warnings.push_back(std::move(message));
}

// Walks the route every 2 m: its length on the road, gaps with no surface
// under it and overhangs lower than a car (each run reported once).
void survey_route(const Surface& s, const RouteLine& r, TrackReport& report) {
    const double step = std::max(2.0, r.length() / 20000.0);
    const auto n = static_cast<std::size_t>(std::ceil(r.length() / step));
    bool in_gap = false, in_low = false;
    double run_start = 0, lowest = 0;
    std::string low_part;
    Vec3 prev = Vec3::Zero(), low_at = Vec3::Zero();
    for (std::size_t i = 0; i <= n; ++i) {
        const double u = std::min(r.length(), static_cast<double>(i) * step);
        RoutePoint p;
        Vec3 dir;
        r.at(u, p, dir);
        Ground g;
        const bool found = ground_at(s, p, g);
        const Vec3 q = found ? g.point : Vec3(p.x, prev.y(), p.z);
        if (i > 0) report.route_length_m += (q - prev).norm();
        if (i < n || report.route.empty()) report.route.push_back(q);
        prev = q;
        if (!found && !in_gap) run_start = u;
        if (found && in_gap) {
            warn(report, "no drivable surface under the route from " + metres(run_start) + " to " + metres(u) +
                             " along it (ending at " + where(q) + ")");
        }
        in_gap = !found;
        std::size_t over = 0;
        const double room = found ? clearance(s, g.point, over) : std::numeric_limits<double>::infinity();
        const bool low = room < kCarHeight_m;
        if (low && (!in_low || room < lowest)) {
            if (!in_low) run_start = u;
            lowest = room;
            low_at = g.point;
            low_part = s.part_of(over);
        }
        if (!low && in_low) {
            warn(report, "clearance " + metres(lowest) + " under '" + low_part + "' at " + where(low_at) + " (route " +
                             metres(run_start) + " to " + metres(u) + "): a car needs " + metres(kCarHeight_m));
        }
        in_low = low;
    }
}

}  // namespace

bool place_gates_and_spawns(const TrackManifest& m, const Surface& s, Track& track, TrackReport& report,
                            std::string& error) {
    std::optional<RouteLine> route;
    if (!m.route.empty()) {
        route.emplace();
        if (!route->build(m.route, error)) return false;
    }
    double start_u = 0;
    const bool ok = m.gates.empty() ? route_gates(m, s, *route, track, error)
                                    : explicit_gates(m, s, route ? &*route : nullptr, track, start_u, error);
    if (!ok || !make_spawns(m, s, route ? &*route : nullptr, start_u, track, error)) return false;
    if (route) survey_route(s, *route, report);
    return true;
}

}  // namespace jetrace::detail
