#include "jetrace/ai/road_profile.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

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

// Height of the highest of `track`'s triangles (found through `grid`, built
// over them) that faces upwards (unit normal's y at least `min_up`) above
// the point (x, z) of the ground plan, between `y_lo` and `y_hi` (unit: m).
// False if there is none.
bool road_height(const Track& track, const UniformGrid& grid, double x, double z, double y_lo, double y_hi,
                 double min_up, double& y) {
    constexpr double kHalf_m = 1e-3;
    const Aabb column{Vec3(x - kHalf_m, y_lo, z - kHalf_m), Vec3(x + kHalf_m, y_hi, z + kHalf_m)};
    bool found = false;
    double best = y_lo;
    // The highest hit wins, whatever the order the grid gives the triangles in.
    grid.for_each_candidate(column, [&](std::uint32_t i) {
        const Triangle& t = track.triangles[i];
        // Inside in the ground plan: the three signed areas agree (edges
        // inclusive; an upward normal makes the winding counter-clockwise).
        // Tested first: it rejects most candidates without the normal.
        const double e0 = cross_xz(t.a, t.b, x, z);
        const double e1 = cross_xz(t.b, t.c, x, z);
        const double e2 = cross_xz(t.c, t.a, x, z);
        const bool inside = (e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0 && e2 <= 0.0);
        if (!inside) return true;
        const Vec3 n = t.normal();
        if (n.y() < min_up) return true;
        const double h = t.a.y() - (n.x() * (x - t.a.x()) + n.z() * (z - t.a.z())) / n.y();
        if (h >= best && h <= y_hi) {
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
    p.first_.reserve(n + 1);
    p.gate_y_.reserve(n);
    double route_m = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        p.gate_y_.push_back(gates[k].center.y());
        route_m += ground_length(gates[(k + n - 1) % n].center, gates[k].center);
    }
    const double spacing_m = std::max(probe.spacing_m, route_m / kMaxRouteSamples);
    for (std::size_t k = 0; k < n; ++k) {
        const Vec3 a = gates[(k + n - 1) % n].center;
        const Vec3 b = gates[k].center;
        // At least one interval.
        const double want = std::ceil(ground_length(a, b) / spacing_m);
        const auto intervals = static_cast<std::uint32_t>(std::clamp(want, 1.0, kMaxIntervals));
        p.first_.push_back(static_cast<std::uint32_t>(p.offsets_.size()));
        for (std::uint32_t j = 0; j <= intervals; ++j) {
            const Vec3 q = a + (b - a) * (static_cast<double>(j) / intervals);
            double y = 0.0;
            const bool ok = road_height(track, grid, q.x(), q.z(), q.y() - probe.below_m, q.y() + probe.above_m,
                                        probe.min_up, y);
            p.offsets_.push_back(ok ? static_cast<std::int16_t>(std::lround((y - q.y()) / kResolution_m)) : kNone);
        }
    }
    p.first_.push_back(static_cast<std::uint32_t>(p.offsets_.size()));
    return p;
}

bool RoadProfile::height(std::int32_t leg, double t, double& y) const {
    const auto n = static_cast<std::int32_t>(legs());
    if (n == 0) return false;
    const auto k = static_cast<std::size_t>(((leg % n) + n) % n);
    const std::uint32_t first = first_[k];
    const std::uint32_t intervals = first_[k + 1] - first - 1;
    const double u = std::clamp(t, 0.0, 1.0);
    const double x = u * intervals;
    const auto j = std::min(static_cast<std::uint32_t>(x), intervals - 1);
    const std::int16_t o0 = offsets_[first + j], o1 = offsets_[first + j + 1];
    if (o0 == kNone || o1 == kNone) return false;
    // The route line is straight along the leg: its height and the offsets
    // interpolate alike.
    const double y0 = gate_y_[(k + legs() - 1) % legs()], y1 = gate_y_[k];
    const double f = x - j;
    y = y0 + (y1 - y0) * u + (o0 + (o1 - o0) * f) * kResolution_m;
    return true;
}

std::size_t RoadProfile::memory_bytes() const {
    return first_.capacity() * sizeof(std::uint32_t) + gate_y_.capacity() * sizeof(double) +
           offsets_.capacity() * sizeof(std::int16_t);
}

}  // namespace jetrace
