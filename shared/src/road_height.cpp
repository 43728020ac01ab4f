#include "road_height.hpp"

namespace jetrace::detail {

namespace {

// Twice the signed area of (a, b, p) in the ground plan (x, z).
double cross_xz(const Vec3& a, const Vec3& b, double x, double z) {
    return (b.x() - a.x()) * (z - a.z()) - (b.z() - a.z()) * (x - a.x());
}

}  // namespace

bool road_height(const Track& track, const UniformGrid& grid, double x, double z, double y_lo, double y_hi, double min_up, double& y) {
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

}  // namespace jetrace::detail
