// A driving AI: follows the gates in order (pure pursuit along the line
// through their centres), brakes for the corners, the crests and the
// obstacles on its route within its braking distance, lifts off in the air,
// thrusts and brakes when it rolls backwards, and when it has made no
// progress for a while drives round the obstacle it is pinned against or
// turns on the spot. Deterministic and stateless: a function of the course
// (the scene and its road profile) and the world (its only memory is the
// car's no-progress counter, part of the state), so an offline race
// reproduces bit for bit and a bot driving a predicted or a snapshot world
// needs nothing else (Pilot, pilot.hpp, runs it at 30 Hz).
//
// It plans no path: it drives the straight line between consecutive gates'
// centres, round a block on it, so a leg that a long wall crosses, or that
// needs a detour to a ramp, is not raced. `jetrace-track inspect` warns of
// such a leg (gate_unreachable).
#pragma once

#include "jetrace/ai/road_profile.hpp"
#include "jetrace/core/world.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace jetrace {

struct DriverSkill {
    /// Lateral acceleration the AI plans corners for (unit: m/s^2); below
    /// the car's grip so it does not drift.
    double corner_mps2 = 30.0;
    /// Longest distance along the route to the point it steers at (unit: m).
    double lookahead_m = 35.0;
    /// Speed to pass a gate that points upwards, such as the top of the
    /// wall (unit: m/s).
    double climb_top_mps = 35.0;
    /// Speed over a crest as a multiple of the speed at which the road
    /// stops holding the car there (unit: ratio). Below 1 because the road
    /// heights the AI samples, 6 m apart, round the sharp folds of terrain
    /// off: they show a larger radius than the road's.
    double crest_ratio = 0.7;
    /// Steering per radian of heading error (unit: lock/rad).
    double steer_gain = 2.5;
};

/// What the AI reads of one scene: the scene, and the road heights along its
/// route, sampled once when the course is made (RoadProfile). Refers to the
/// scene, which must outlive it.
class Course {
public:
    /// Places across a gate the AI tries, each side of the centre (the
    /// centre is place 0; place 2k - 1 is k steps to one side, 2k the other).
    static constexpr int kCrossingSteps = 8;

    explicit Course(const Scene& scene, const RoadProbe& probe = {});

    const Scene& scene() const { return *scene_; }
    const RoadProfile& road() const { return road_; }
    /// True if a static part of the track (a face steeper than the road:
    /// a block, a barrier) stands where a car would cross gate `gate` at
    /// place `place` (0 .. 2 kCrossingSteps): on the line or before it, or
    /// (unless `finishing`: a car that finishes stops there) just after it.
    bool crossing_blocked(std::size_t gate, int place, bool finishing) const {
        return ((finishing ? at_line_[gate] : blocked_[gate]) >> place) & 1u;
    }
    /// How far across gate `gate` from its centre the first place
    /// crossing_blocked() leaves free is (unit: m; 0 if none is): where a
    /// car crosses when no finished car is in the way.
    double first_free_place_m(std::size_t gate, bool finishing) const {
        return (finishing ? free_at_line_m_ : free_m_)[gate];
    }

private:
    const Scene* scene_;
    RoadProfile road_;
    // One bit a place, per gate: up to the line, and up to 4 m past it.
    std::vector<std::uint32_t> at_line_;
    std::vector<std::uint32_t> blocked_;
    // first_free_place_m() per gate, for each of the two.
    std::vector<double> free_at_line_m_;
    std::vector<double> free_m_;
};

/// The Course of whichever scene a client races on, made again when that
/// scene changes (a client that adopts a downloaded track, say). A scene is
/// taken to be the one before if it is at the same address with as many
/// triangles and gates.
class CourseCache {
public:
    const Course& operator()(const Scene& scene);

private:
    std::optional<Course> course_;
    std::size_t triangles_ = 0;
    std::size_t gates_ = 0;
};

/// The input the AI gives car `slot` for the next tick. `stepped`, if
/// given, is the car's scratch from the step that made `state` on the
/// course's scene: where it kept the contacts at the car's very position,
/// they tell whether the car is on the track (the same answer as the AI's
/// own query, which it then skips).
Input drive(const Course& course, const WorldState& state, int slot, const DriverSkill& skill = {},
            const CarScratch* stepped = nullptr);

}  // namespace jetrace
