#include "jetrace/resolver.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace {

bool Candidates::covers(const Vec3& p, double radius_m) const {
    if (all) return true;
    const Vec3 d = (p - center).cwiseAbs();
    const double slack = reach_m - radius_m;
    return d.x() <= slack && d.y() <= slack && d.z() <= slack;
}

void gather_candidates(const UniformGrid& grid, Broadphase bp, const Vec3& center,
                       double radius_m, Candidates& out) {
    out.center = center;
    out.reach_m = radius_m;
    out.triangles.clear();
    out.all = bp == Broadphase::brute_force;
    if (out.all) return;
    grid.for_each_candidate(Aabb::around(center, radius_m), [&](std::uint32_t t) { out.triangles.push_back(t); });
    // Canonical order: ascending triangle index, the brute-force order. The
    // result of a step then does not depend on which cells were visited or
    // on how large the gathered region was, only on the geometry.
    std::sort(out.triangles.begin(), out.triangles.end());
}

namespace {

// Calls f(triangle) for each candidate in a fixed order.
template <class F>
void for_each(const Track& track, const Candidates& cand, F&& f) {
    if (cand.all) {
        for (const Triangle& t : track.triangles) {
            if (!f(t)) return;
        }
    } else {
        for (std::uint32_t i : cand.triangles) {
            if (!f(track.triangles[i])) return;
        }
    }
}

// Direction from the surface point `q` to the centre `p`; if the centre lies
// on the triangle, the face normal on the side the car came from.
Vec3 contact_normal(const Triangle& t, const Vec3& q, const Vec3& p, double dist, const Vec3& came_from) {
    if (dist > 1e-9) return (p - q) / dist;
    if (t.degenerate) return kWorldUp;
    return (came_from - q).dot(t.normal) < 0.0 ? Vec3(-t.normal) : t.normal;
}

// Cheap exact rejection: a sphere farther than `reach` from the triangle's
// plane cannot be within `reach` of the triangle.
inline bool beyond_plane(const Triangle& t, const Vec3& p, double reach) {
    if (t.degenerate) return false;
    const double d = (p - t.a).dot(t.normal);
    return d > reach || d < -reach;
}

}  // namespace

void find_contacts(const Track& track, const Candidates& cand, const PhysicsSettings& s, const Vec3& center,
                   Contacts& out) {
    out.clear();
    const double reach = s.car_radius_m + s.contact_skin_m;
    const double reach2 = reach * reach;
    for_each(track, cand, [&](const Triangle& t) {
        if (beyond_plane(t, center, reach)) return true;
        const Vec3 q = closest_point_on_triangle(center, t).point;
        const double d2 = (center - q).squaredNorm();
        if (d2 < reach2) out.add(contact_normal(t, q, center, std::sqrt(d2), center + t.normal));
        return true;
    });
}

ResolveStats resolve(const Track& track, const UniformGrid& grid, Broadphase bp, const PhysicsSettings& s,
                     const Vec3& previous_position, Vec3& position, Vec3& velocity, Candidates& cand) {
    ResolveStats stats;
    const double r = s.car_radius_m;
    const double r2 = r * r;
    const double target = r + s.resolver_epsilon_m;
    const double query_radius = r + s.contact_skin_m;
    if (!cand.covers(position, query_radius)) {
        gather_candidates(grid, bp, position, query_radius + kGatherMargin_m, cand);
    }
    for (int pass = 0; pass < s.resolver_passes; ++pass) {
        bool pushed = false;
        for_each(track, cand, [&](const Triangle& t) {
            if (beyond_plane(t, position, r)) return true;
            const Vec3 q = closest_point_on_triangle(position, t).point;
            const double d2 = (position - q).squaredNorm();
            if (d2 > r2) return true;  // not touching: next triangle
            const double dist = std::sqrt(d2);
            const Vec3 n = contact_normal(t, q, position, dist, previous_position);
            position = q + n * target;
            const double vn = velocity.dot(n);
            if (vn < 0.0) velocity -= n * vn;  // inelastic: no velocity into the surface
            pushed = true;
            return false;  // one push per pass
        });
        if (!pushed) break;
        ++stats.pushes;
        if (!cand.covers(position, query_radius)) {
            gather_candidates(grid, bp, position, query_radius + kGatherMargin_m, cand);
        }
    }
    if (stats.pushes == s.resolver_passes) {
        // Did the last push leave the car clear?
        for_each(track, cand, [&](const Triangle& t) {
            const Vec3 q = closest_point_on_triangle(position, t).point;
            if ((position - q).squaredNorm() < r2) {
                stats.capped = true;
                return false;
            }
            return true;
        });
    }
    return stats;
}

}  // namespace jetrace
