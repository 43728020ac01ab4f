#include "ground_probe.hpp"

#include "track_raycast.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace jetrace::detail {
namespace {

// Half the width of a vertical probe's box (unit: m): the grid is asked for
// the triangles of a thin column around the line.
constexpr double kColumnHalf_m = 1e-3;

// Twice the signed area of (a, b, p) in the ground plan (x, z).
double cross_xz(const Vec3& a, const Vec3& b, double x, double z) {
    return (b.x() - a.x()) * (z - a.z()) - (b.z() - a.z()) * (x - a.x());
}

}  // namespace

bool finite(const Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

std::string at(const Vec3& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.1f, %.1f, %.1f)", v.x(), v.y(), v.z());
    return buf;
}

void column_hits(const Track& track, const UniformGrid& grid, double x, double z, double y_lo, double y_hi,
                 std::vector<ColumnHit>& out) {
    out.clear();
    const Aabb column{Vec3(x - kColumnHalf_m, y_lo, z - kColumnHalf_m), Vec3(x + kColumnHalf_m, y_hi, z + kColumnHalf_m)};
    grid.for_each_candidate(column, [&](std::uint32_t i) {
        const Triangle& t = track.triangles[i];
        if (t.degenerate) return;
        // Inside in the ground plan: the three signed areas agree (edges inclusive).
        const double e0 = cross_xz(t.a, t.b, x, z);
        const double e1 = cross_xz(t.b, t.c, x, z);
        const double e2 = cross_xz(t.c, t.a, x, z);
        if (!((e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0 && e2 <= 0.0))) return;
        Vec3 n = t.normal();
        if (!(std::abs(n.y()) > 1e-9)) return;  // parallel to the probe
        if (n.y() < 0.0) n = -n;
        const double h = t.a.y() - (n.x() * (x - t.a.x()) + n.z() * (z - t.a.z())) / n.y();
        if (h >= y_lo && h <= y_hi) out.push_back({h, n});
    });
}

bool cast_ray(const Track& track, const UniformGrid& grid, const Vec3& o, const Vec3& d, double max_t, double& t,
              std::uint32_t& triangle) {
    const Vec3 end = o + d * max_t;
    if (!finite(o) || !finite(end)) return false;
    const Vec3 pad(1e-3, 1e-3, 1e-3);
    const Aabb box{o.cwiseMin(end) - pad, o.cwiseMax(end) + pad};
    bool found = false;
    grid.for_each_candidate(box, [&](std::uint32_t i) {
        const Triangle& tri = track.triangles[i];
        double hit = 0;
        if (tri.degenerate || !ray_triangle(tri, o, d, hit)) return;
        if (hit < -1e-9 || hit > max_t || (found && hit >= t)) return;
        found = true;
        t = hit;
        triangle = i;
    });
    return found;
}

}  // namespace jetrace::detail
