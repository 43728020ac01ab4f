// gate_unreachable: each leg walked in the vertical section along the
// straight ground-plan line between the roads under two consecutive gates
// (their respawn points: the car resting on the road under the gate).
// Every sample_spacing_m a vertical probe lists the surfaces in the column;
// the car's ground goes on over the highest one that continues the last
// ground's face (the two faces' lines in the section meet between the
// samples: a fold, however steep, not a step), else drops (or steps up at
// most max_step_up_m) onto the highest one below, else the leg fails. No
// slope limit applies: a moving car rides up any continuous face (the
// stadium's 85 degree wall); only a sharp concave crease into a face
// steeper than the ride limit stops it.
#include "drivability_legs.hpp"

#include "ground_probe.hpp"
#include "track_raycast.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace jetrace::detail {
namespace {

// How far two faces' lines may miss each other and still join (unit: m):
// meshes have small cracks and overlaps at their seams.
constexpr double kJoinSlack_m = 0.1;
// Most probes over all legs: a longer route (or a hostile file's) is
// sampled wider apart than asked.
constexpr double kMaxTotalSamples = 1 << 20;
constexpr double kRadToDeg = 57.29577951308232;

// The ground in the leg's vertical section: along the leg (s), height (y),
// the face's unit normal in the section (ms along s, my up, my > 0); and in
// 3D, the point and the face's unit normal (facing up).
struct Ground {
    double s = 0, y = 0, ms = 0, my = 1;
    Vec3 p{0, 0, 0}, n{0, 1, 0};
};

Ground ground_of(double s, const Vec3& p, const Vec3& n, double ux, double uz) {
    const double ms = n.x() * ux + n.z() * uz, my = n.y();
    const double len = std::sqrt(ms * ms + my * my);
    return {s, p.y(), ms / len, my / len, p, n};
}

// The faces' lines in the section meet between (or within the slack of)
// the two samples, or one sample lies on the other's line.
bool continuous(const Ground& a, const Ground& b) {
    const double ds = b.s - a.s, dy = b.y - a.y;
    if (std::abs(a.ms * ds + a.my * dy) <= kJoinSlack_m || std::abs(b.ms * ds + b.my * dy) <= kJoinSlack_m) {
        return true;
    }
    const double det = a.ms * b.my - a.my * b.ms;
    if (!(std::abs(det) > 1e-12)) return false;
    const double ca = a.ms * a.s + a.my * a.y, cb = b.ms * b.s + b.my * b.y;
    const double s = (ca * b.my - cb * a.my) / det;
    const double y = (a.ms * cb - b.ms * ca) / det;
    return s >= a.s - kJoinSlack_m && s <= b.s + kJoinSlack_m && y >= std::min(a.y, b.y) - kJoinSlack_m &&
           y <= std::max(a.y, b.y) + kJoinSlack_m;
}

// Angle of the face's rise along the leg, and the concave fold from a to b
// (unit: degrees; positive: the surface turns upwards).
double rise_deg(const Ground& g) { return std::atan2(-g.ms, g.my) * kRadToDeg; }
double fold_deg(const Ground& a, const Ground& b) { return rise_deg(b) - rise_deg(a); }

struct Leg {
    Vec3 from, to;  // the roads under the two gates
    Vec3 from_up;   // the face under the first
    double length_m = 0, ux = 1, uz = 0;
};

// One leg's walk; a non-empty reason when it fails.
class Walk {
public:
    Walk(const Track& track, const UniformGrid& grid, const DrivabilityLimits& lim, const Leg& leg)
        : track_(track), grid_(grid), lim_(lim), leg_(leg) {}

    std::string run(double spacing_m) {
        const auto intervals = static_cast<std::int64_t>(std::clamp(std::ceil(leg_.length_m / spacing_m), 1.0, 1e7));
        const Vec3 up = leg_.from_up.y() < 0 ? Vec3(-leg_.from_up) : leg_.from_up;
        g_ = ground_of(0, leg_.from, up, leg_.ux, leg_.uz);
        for (std::int64_t j = 1; j <= intervals; ++j) {
            const double s = leg_.length_m * static_cast<double>(j) / static_cast<double>(intervals);
            if (std::string why = step(s); !why.empty()) return why;
        }
        char buf[240];
        if (air_from_ >= 0) {
            std::snprintf(buf, sizeof buf, "no surface under it from %.1f m to the gate (a %.1f m leg)", air_from_,
                          leg_.length_m);
            return buf;
        }
        if (!(std::abs(g_.y - leg_.to.y()) <= lim_.arrive_tolerance_m)) {
            std::snprintf(buf, sizeof buf, "the leg (%.1f m) ends %.1f m %s the road under the gate (another level)",
                          leg_.length_m, std::abs(g_.y - leg_.to.y()), g_.y > leg_.to.y() ? "above" : "below");
            return buf;
        }
        return {};
    }

private:
    std::string where(double s) const {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.1f m of the %.1f m leg", s, leg_.length_m);
        return buf;
    }

    // The next sample, s along the leg: the ground moves on, or a reason.
    std::string step(double s) {
        const double x = leg_.from.x() + leg_.ux * s, z = leg_.from.z() + leg_.uz * s;
        column_hits(track_, grid_, x, z, track_.bounds.min.y() - 1.0, track_.bounds.max.y() + 1.0, hits_);
        Ground on, below;
        double lowest_above = INFINITY;
        bool any_on = false, any_below = false;
        for (const ColumnHit& h : hits_) {
            const Ground c = ground_of(s, Vec3(x, h.y, z), h.normal, leg_.ux, leg_.uz);
            if (continuous(g_, c) && (!any_on || c.y > on.y)) on = c, any_on = true;
            if (c.y <= g_.y + lim_.max_step_up_m && (!any_below || c.y > below.y)) below = c, any_below = true;
            if (c.y > g_.y + lim_.max_step_up_m) lowest_above = std::min(lowest_above, c.y);
        }
        char buf[240];
        if (!any_on && !any_below && !hits_.empty()) {
            std::snprintf(buf, sizeof buf, "a step up of %.1f m at %s, at %s", lowest_above - g_.y, where(s).c_str(),
                          at(Vec3(x, g_.y, z)).c_str());
            return buf;
        }
        if (!any_on && !any_below) {
            if (air_from_ < 0) air_from_ = g_.s;
            if (!(s - air_from_ > lim_.max_gap_m)) return {};
            std::snprintf(buf, sizeof buf, "no surface under it from %.1f m to %s (the last ground at %s)", air_from_,
                          where(s).c_str(), at(g_.p).c_str());
            return buf;
        }
        const Ground next = any_on ? on : below;
        if (any_on && fold_deg(g_, on) > lim_.max_crease_deg && rise_deg(on) > lim_.ride_limit_deg) {
            std::snprintf(buf, sizeof buf, "a crease of %.0f degrees into a face rising at %.0f degrees at %s, at %s",
                          fold_deg(g_, on), rise_deg(on), where(s).c_str(), at(on.p).c_str());
            return buf;
        }
        // A wall between the two samples, higher than a step: the segment
        // between the points a step's height above each ground (not for a
        // drop: the car falls, and a ray from its last ground would meet the
        // edge it falls from).
        if (any_on || next.y > g_.y) {
            const Vec3 a = g_.p + g_.n * lim_.max_step_up_m, b = next.p + next.n * lim_.max_step_up_m;
            const double len = (b - a).norm();
            double t = 0;
            std::uint32_t tri = 0;
            if (len > 0 && cast_ray(track_, grid_, a, (b - a) / len, len, t, tri)) {
                const Vec3 hit = a + (b - a) * (t / len);
                std::snprintf(buf, sizeof buf, "a wall (%.0f degrees) at %s, at %s", slope_of(track_.triangles[tri]),
                              where(s).c_str(), at(hit).c_str());
                return buf;
            }
        }
        g_ = next;
        air_from_ = -1;
        return {};
    }

    static double slope_of(const Triangle& t) { return std::acos(std::min(1.0, std::abs(t.normal().y()))) * kRadToDeg; }

    const Track& track_;
    const UniformGrid& grid_;
    const DrivabilityLimits& lim_;
    const Leg& leg_;
    Ground g_;
    double air_from_ = -1;  // where the ground under the leg ended, or -1
    std::vector<ColumnHit> hits_;
};

}  // namespace

void check_legs(const Track& track, const UniformGrid& grid, const DrivabilityLimits& limits,
                std::vector<DrivabilityWarning>& out) {
    const auto& gates = track.checkpoints;
    const std::size_t n = gates.size();
    if (n < 2) return;
    // The road under a gate: its respawn pose less the car's resting height.
    auto road = [&](std::size_t k) { return gates[k].respawn.position - gates[k].respawn.up * kRest_m; };
    double total_m = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const Vec3 d = road(k) - road((k + n - 1) % n);
        if (finite(d)) total_m += std::hypot(d.x(), d.z());
    }
    const double spacing_m = std::max(limits.sample_spacing_m, total_m / kMaxTotalSamples);
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t prev = (k + n - 1) % n;
        Leg leg{road(prev), road(k), gates[prev].respawn.up};
        if (!finite(leg.from) || !finite(leg.to) || !finite(leg.from_up) || !(std::abs(leg.from_up.y()) > 1e-9)) continue;
        leg.length_m = std::hypot(leg.to.x() - leg.from.x(), leg.to.z() - leg.from.z());
        if (leg.length_m > 0) {
            leg.ux = (leg.to.x() - leg.from.x()) / leg.length_m;
            leg.uz = (leg.to.z() - leg.from.z()) / leg.length_m;
        }
        const std::string why = Walk(track, grid, limits, leg).run(spacing_m);
        if (why.empty()) continue;
        out.push_back({kGateUnreachable, "gate", static_cast<std::int64_t>(k), gates[k].center,
                       "gate " + std::to_string(k) + " at " + at(gates[k].center) + " is not reachable from gate " +
                           std::to_string(prev) + " over a continuous surface: " + why});
    }
}

}  // namespace jetrace::detail
