// Sphere against track: candidate gathering and the seed's push-out.
#pragma once

#include "jetrace/contacts.hpp"
#include "jetrace/settings.hpp"
#include "jetrace/track.hpp"
#include "jetrace/uniform_grid.hpp"

#include <cstdint>
#include <vector>

namespace jetrace {

/// How the resolver finds the triangles near a car.
enum class Broadphase : std::uint8_t { grid, brute_force };

/// The triangles near a car, gathered once per step and reused by every
/// push-out pass while the car stays within `reach` of where they were
/// gathered. The vector is scratch owned by the caller (no allocation once
/// warm).
struct Candidates {
    std::vector<std::uint32_t> triangles;
    Vec3 center{0, 0, 0};
    double reach_m = 0;
    bool all = false;  // brute force: every triangle

    /// True if a sphere of `radius_m` at `p` is inside the gathered region.
    bool covers(const Vec3& p, double radius_m) const;
};

/// Gathers the triangles that may touch a sphere of `radius_m` at `center`
/// (grid query or all triangles).
/// Extra reach added around a car when its candidates are gathered, so
/// they stay valid while small pushes move it (unit: m).
inline constexpr double kGatherMargin_m = 0.5;

void gather_candidates(const UniformGrid& grid, Broadphase bp, const Vec3& center,
                       double radius_m, Candidates& out);

/// Contacts within radius + skin of `center` among the candidates.
void find_contacts(const Track& track, const Candidates& cand, const PhysicsSettings& s, const Vec3& center,
                   Contacts& out);

struct ResolveStats {
    /// Passes that pushed the car this step (the pass after them found it clear,
    /// unless they reached resolver_passes).
    int passes = 0;
    /// Push-outs performed this step (one per pass with PushOut::first_contact).
    int pushes = 0;
    /// First contacts met by the swept test this step (CollisionMode::swept).
    int sweep_hits = 0;
    /// True if the pass cap stopped the resolver with the car still inside a triangle.
    bool capped = false;
};

/// In CollisionMode::swept, a car that moved more than half its radius since
/// `previous_position` is first swept along that motion (sweep.hpp). Then
/// the seed's discrete push-out, made safe: up to resolver_passes passes,
/// each going through the candidate triangles in ascending order and, for
/// every one the sphere touches or penetrates (distance <= radius), moving
/// the centre to radius + epsilon from its closest point and removing the
/// velocity into it (PushOut::first_contact: only the first per pass). Stops
/// after a pass that pushed nothing. With epsilon 0 a pushed-out triangle
/// still counts as touching and eats every pass (the seed's fall through the
/// ground). Re-gathers candidates if pushes carry the car out of their reach;
/// the result does not depend on where they were gathered.
ResolveStats resolve(const Track& track, const UniformGrid& grid, Broadphase bp, const PhysicsSettings& s,
                     const Vec3& previous_position, Vec3& position, Vec3& velocity, Candidates& cand);

}  // namespace jetrace
