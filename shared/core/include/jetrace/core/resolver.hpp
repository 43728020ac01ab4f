// Sphere against track: candidate gathering and the seed's push-out.
#pragma once

#include "jetrace/core/candidates.hpp"
#include "jetrace/core/contacts.hpp"
#include "jetrace/core/settings.hpp"
#include "jetrace/core/track.hpp"
#include "jetrace/core/uniform_grid.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace jetrace {

/// How the resolver finds the triangles near a car.
enum class Broadphase : std::uint8_t { grid, brute_force };

/// What every resolver query reads: the track, its grid, how candidates are
/// found and the physics settings (Scene::query() makes one).
struct TrackQuery {
    const Track& track;
    const UniformGrid& grid;
    Broadphase broadphase;
    const PhysicsSettings& physics;
};

/// The car a resolve() moves: where it was before this step's motion, where
/// the motion left it, and its velocity (both updated).
struct SphereMotion {
    const Vec3& from;
    Vec3& position;
    Vec3& velocity;
};

/// Extra reach added around a car when its candidates are gathered, so
/// they stay valid while small pushes move it (unit: m).
inline constexpr double kGatherMargin_m = 0.5;
/// Steps of travel at the car's current speed that a gather looks ahead
/// (unit: steps); see Candidates::lookahead. Other values are compared in
/// docs/ACCURACY.md ("Side by side with Bullet").
inline constexpr double kGatherLookahead_steps = 12.0;
/// The look-ahead of a car whose last region served at least
/// kGatherLookahead_steps steps (unit: steps): its path followed its
/// velocity, so a region twice as long saves every other gather. A car
/// whose region ended sooner (it turned, hit something or was placed
/// elsewhere) looks kGatherLookahead_steps ahead, so that a path its
/// velocity does not predict pays for no longer region.
inline constexpr double kGatherLookaheadLong_steps = 24.0;
/// The look-ahead of a car whose last region served at least
/// kGatherLookaheadLong_steps steps (unit: steps): twice as long again
/// (a car on a long straight), within kGatherLookaheadMax_m.
inline constexpr double kGatherLookaheadLongest_steps = 48.0;
/// Longest look-ahead (unit: m), so that a car far above the top speed
/// (365 m/s: 146 m in 48 steps) does not gather a long corridor.
inline constexpr double kGatherLookaheadMax_m = 50.0;

/// Gathers the triangles whose grid boxes (their bounds rounded outward to
/// floats, UniformGrid::box) overlap the box around the cube of half-edge
/// `radius_m` at `center` and the same cube moved by out.lookahead (grid
/// query, then a test of each box), in ascending index order, each once; or
/// marks all triangles (brute force).
void gather_candidates(const TrackQuery& q, const Vec3& center, double radius_m, Candidates& out);

/// What a query needs its candidates for, which decides how far they reach.
enum class GatherFor : std::uint8_t {
    contacts,  ///< the contacts where the car is (and the push-out's passes)
    step,      ///< a step moving the car by `motion_m`, its contacts and its sweep
    sweep,     ///< a sweep along a motion of `motion_m`, and the push-out after it
};

/// How far around a car its candidates must reach (unit: m): they are
/// gathered again when they do not cover a sphere of `cover_m`, and then
/// over a cube of half-edge `gather_m`, so that small moves keep them valid.
struct GatherReach {
    double cover_m;
    double gather_m;
};

/// The gather policy, the one place that decides candidate reach.
inline GatherReach gather_reach(const PhysicsSettings& s, GatherFor why, double motion_m = 0.0);

/// gather_reach(s, GatherFor::step, motion_m).cover_m alone: what a step
/// checks its candidates against every time, before it knows whether it
/// gathers.
inline double step_cover(const PhysicsSettings& s, double motion_m) {
    return s.car_radius_m + s.contact_skin_m + motion_m;
}

/// The look-ahead a car moving at `velocity` gathers with (see
/// Candidates::lookahead), `travel_m` being its motion in one step and
/// `served_steps` the steps its last region served (Candidates::steps_served).
inline Vec3 gather_lookahead(const PhysicsSettings& s, const Vec3& velocity, double travel_m,
                             std::uint32_t served_steps);

/// Gathers the candidates again around `p` unless they cover `reach`.
/// True if it gathered.
inline bool keep_covered(const TrackQuery& q, const Vec3& p, const GatherReach& reach, Candidates& cand) {
    if (cand.covers(p, reach.cover_m)) return false;
    gather_candidates(q, p, reach.gather_m, cand);
    return true;
}

/// Contacts within radius + skin of `center` among the candidates.
void find_contacts(const TrackQuery& q, const Candidates& cand, const Vec3& center, Contacts& out);

/// True if resolve() sweeps a car that moved from `from` to `to`: in
/// CollisionMode::swept, a motion of more than half the radius.
inline bool needs_sweep(const PhysicsSettings& s, const Vec3& from, const Vec3& to) {
    const double half_r = 0.5 * s.car_radius_m;
    return s.collision_mode == CollisionMode::swept && (to - from).squaredNorm() > half_r * half_r;
}

/// How far around its start a sweep of `motion_m` needs candidates (unit: m):
/// every slide stays within the motion's length of the start, plus epsilon
/// per contact, plus the push-out's reach and kGatherMargin_m.
inline double sweep_reach(const PhysicsSettings& s, double motion_m) {
    return motion_m + s.sweep_contacts * s.resolver_epsilon_m + s.car_radius_m + s.contact_skin_m + kGatherMargin_m;
}

// Definitions of gather_reach and gather_lookahead (inline: a step asks several times).
inline GatherReach gather_reach(const PhysicsSettings& s, GatherFor why, double motion_m) {
    switch (why) {
        case GatherFor::contacts: {
            const double cover = s.car_radius_m + s.contact_skin_m;
            return {cover, cover + kGatherMargin_m};
        }
        case GatherFor::sweep: {
            const double cover = sweep_reach(s, motion_m);
            return {cover, cover + kGatherMargin_m};
        }
        case GatherFor::step: break;
    }
    // A step: wide enough for the step's sweep too (its motion is about
    // motion_m; kGatherMargin_m absorbs the step's acceleration), so that
    // the sweep does not gather again.
    const double cover = step_cover(s, motion_m);
    const double reach = cover + kGatherMargin_m;
    const double gather =
        s.collision_mode == CollisionMode::swept ? std::max(reach, sweep_reach(s, motion_m) + kGatherMargin_m) : reach;
    return {cover, gather};
}

inline Vec3 gather_lookahead(const PhysicsSettings& s, const Vec3& velocity, double travel_m,
                             std::uint32_t served_steps) {
    double steps = kGatherLookahead_steps;
    if (served_steps >= static_cast<std::uint32_t>(kGatherLookaheadLong_steps)) {
        steps = kGatherLookaheadLongest_steps;
    } else if (served_steps >= static_cast<std::uint32_t>(kGatherLookahead_steps)) {
        steps = kGatherLookaheadLong_steps;
    }
    Vec3 lookahead = velocity * (s.dt_s() * steps);
    const double ahead = travel_m * steps;
    if (ahead > kGatherLookaheadMax_m) lookahead *= kGatherLookaheadMax_m / ahead;
    return lookahead;
}

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
    /// True if `contacts` holds what find_contacts() finds where the car
    /// ends (the last pass pushed nothing and collected them).
    bool found_contacts = false;
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
/// the result does not depend on where they were gathered. With
/// quantize_state, the car is rounded to the wire resolution after the sweep
/// and after every pushing pass, so the pass that finds it clear runs where
/// it ends; that pass also finds its contacts (ResolveStats::found_contacts).
/// `expect_push` (a car pushed in its last step, such as one pressed into a
/// corner) only saves work: the first pass then skips the contacts, which a
/// pushing pass would throw away. Results never depend on it.
ResolveStats resolve(const TrackQuery& q, const SphereMotion& car, Candidates& cand, Contacts& contacts,
                     bool expect_push = false);

}  // namespace jetrace
