#include "jetrace/ai/road_profile.hpp"

#include "ai_math.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace jetrace {

namespace {

// Most samples on one leg, less one, and on the whole route: a longer
// route (or a hostile file's) is sampled wider apart than asked.
constexpr double kMaxIntervals = 4096.0;
constexpr double kMaxRouteSamples = 1 << 20;

double ground_length(const Vec3& a, const Vec3& b) {
    const double dx = b.x() - a.x(), dz = b.z() - a.z();
    return std::sqrt(dx * dx + dz * dz);
}

// Twice the signed area of (a, b, p) in the ground plan (x, z).
double cross_xz(const Vec3& a, const Vec3& b, double x, double z) {
    return (b.x() - a.x()) * (z - a.z()) - (b.z() - a.z()) * (x - a.x());
}

// A car drives up a step at most this high onto a higher face (half its
// radius: the push at a higher edge is more than 60 degrees from the
// vertical), else on over the highest face below (unit: m).
constexpr double kStepUp_m = 1.25;

// Height of the road above the point (x, z) of the ground plan among
// `track`'s triangles (found through `grid`, built over them) that slope
// like a road (|unit normal's y| at least `min_up`, wound either way) and
// lie between `y_lo` and `y_hi`: the highest at or below `reach` (unit: m).
// False if there is none. `higher` is set if one lies above `reach`.
bool road_height(const Track& track, const UniformGrid& grid, double x, double z, double y_lo, double y_hi,
                 double reach, double min_up, double& y, bool& higher) {
    constexpr double kHalf_m = 1e-3;
    const Aabb column{Vec3(x - kHalf_m, y_lo, z - kHalf_m), Vec3(x + kHalf_m, y_hi, z + kHalf_m)};
    bool found = false;
    higher = false;
    double best = y_lo;
    // The highest hit wins, whatever the order the grid gives the triangles in.
    grid.for_each_candidate(column, [&](std::uint32_t i) {
        const Triangle& t = track.triangles[i];
        // Inside in the ground plan: the three signed areas agree (edges
        // inclusive, either winding). Tested first: it rejects most
        // candidates without the normal.
        const double e0 = cross_xz(t.a, t.b, x, z);
        const double e1 = cross_xz(t.b, t.c, x, z);
        const double e2 = cross_xz(t.c, t.a, x, z);
        const bool inside = (e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0 && e2 <= 0.0);
        if (!inside) return true;
        const Vec3 n = t.normal();
        if (!(std::abs(n.y()) >= min_up)) return true;
        const double h = t.a.y() - (n.x() * (x - t.a.x()) + n.z() * (z - t.a.z())) / n.y();
        if (h > reach && h >= y_lo && h <= y_hi) higher = true;
        if (h >= best && h <= y_hi && h <= reach) {
            best = h;
            found = true;
        }
        return true;
    });
    y = best;
    return found;
}

}  // namespace

RoadProfile RoadProfile::build(const Track& track, const UniformGrid& grid, const RoadProbe& probe) {
    assert(probe.spacing_m > 0.0);
    assert(probe.above_m >= 0.0 && probe.above_m <= 32.0 && probe.below_m >= 0.0 && probe.below_m <= 32.0);
    RoadProfile p;
    const auto& gates = track.checkpoints;
    const std::size_t n = gates.size();
    if (n == 0) return p;
    p.legs_.reserve(n);
    double route_m = 0.0;
    for (std::size_t k = 0; k < n; ++k) route_m += ground_length(gates[(k + n - 1) % n].center, gates[k].center);
    const double spacing_m = std::max(probe.spacing_m, route_m / kMaxRouteSamples);
    for (std::size_t k = 0; k < n; ++k) {
        const Vec3 a = gates[(k + n - 1) % n].center;
        const Vec3 b = gates[k].center;
        // At least one interval.
        const double want = std::ceil(ground_length(a, b) / spacing_m);
        const auto intervals = static_cast<std::uint32_t>(std::clamp(want, 1.0, kMaxIntervals));
        p.legs_.push_back({static_cast<std::uint32_t>(p.points_.size()), intervals, a.y(), b.y()});
        // The road a car drives on along the leg: from under the gate it
        // starts at (the highest road below the route line there), on over
        // the highest road at most a step above the last one, so that a
        // ceiling or a deck overhead is not read as road whichever way its
        // faces are wound. After a stretch with none, the highest within
        // the probe.
        bool last_ok = false;
        double last_y = 0.0;
        for (std::uint32_t j = 0; j <= intervals; ++j) {
            const Vec3 q = a + (b - a) * (static_cast<double>(j) / intervals);
            const double lo = q.y() - probe.below_m, hi = q.y() + probe.above_m;
            const double reach = j == 0 ? q.y() : last_ok ? last_y + kStepUp_m : hi;
            double y = 0.0;
            bool higher = false;
            const bool ok = road_height(track, grid, q.x(), q.z(), lo, hi, reach, probe.min_up, y, higher);
            // A top more than a step above the road driven on: an obstacle
            // (a block, a deck's edge) stands there, not on the first sample
            // (under the gate, where the start has no last road).
            p.points_.push_back({ok ? static_cast<std::int16_t>(std::lround((y - q.y()) / kResolution_m)) : kNone,
                                 static_cast<std::uint8_t>(j > 0 && last_ok && higher ? 1 : 0)});
            last_ok = ok;
            last_y = y;
        }
    }
    p.level_.reserve(n);
    for (std::size_t k = 0; k < n; ++k) p.level_.push_back(p.level_of(p.legs_[k]));
    return p;
}

double RoadProfile::level_of(const Leg& l) const {
    const Point* at = &points_[l.first];
    bool level = l.y0 == l.y1 && at[0].offset != kNone;
    for (std::uint32_t j = 0; level && j <= l.intervals; ++j) {
        level = at[j].offset == at[0].offset && at[j].obstacle == 0;
    }
    if (!level) return std::numeric_limits<double>::quiet_NaN();
    // sample()'s sum with both differences zero: the same bits at every t.
    return l.y0 + (l.y1 - l.y0) * 0.0 + at[0].offset * kResolution_m;
}

double RoadProfile::level_height(std::int32_t leg) const {
    const auto n = static_cast<std::int32_t>(level_.size());
    if (n == 0) return std::numeric_limits<double>::quiet_NaN();
    return level_[static_cast<std::size_t>(ai_detail::wrap(leg, n))];
}

bool RoadProfile::obstacle(std::int32_t leg, double t) const { return sample(leg, t).obstacle; }

bool RoadProfile::height(std::int32_t leg, double t, double& y) const {
    const Sample s = sample(leg, t);
    if (s.has_height) y = s.y;
    return s.has_height;
}

RoadProfile::Sample RoadProfile::sample(std::int32_t leg, double t) const {
    Sample out;
    const auto n = static_cast<std::int32_t>(legs_.size());
    if (n == 0) return out;
    // The point falls between samples `at` and `at` + 1 of its leg, a
    // fraction `f` of the way.
    const Leg& l = legs_[static_cast<std::size_t>(ai_detail::wrap(leg, n))];
    const double u = std::clamp(t, 0.0, 1.0);
    const double x = u * l.intervals;
    const auto j = std::min(static_cast<std::uint32_t>(x), l.intervals - 1);
    const Point* at = &points_[l.first + j];
    const double f = x - j;
    out.obstacle = at[0].obstacle != 0 || at[1].obstacle != 0;
    const std::int16_t o0 = at[0].offset, o1 = at[1].offset;
    if (o0 == kNone || o1 == kNone) return out;
    // The route line is straight along the leg: its height and the offsets
    // interpolate alike.
    out.y = l.y0 + (l.y1 - l.y0) * u + (o0 + (o1 - o0) * f) * kResolution_m;
    out.has_height = true;
    return out;
}

std::size_t RoadProfile::memory_bytes() const {
    return legs_.capacity() * sizeof(Leg) + points_.capacity() * sizeof(Point) + level_.capacity() * sizeof(double);
}

}  // namespace jetrace
