// A driving AI: follows the gates in order (pure pursuit along the line
// through their centres), brakes for the corners and the crests within its
// braking distance, lifts off in the air, and turns on the spot when it has made no
// progress for a while. Deterministic and stateless: a function of the course
// (the scene and its road profile) and the world (its only memory is the car's no-progress counter, part of
// the state), so an offline race reproduces bit for bit and a bot driving a
// predicted or a snapshot world needs nothing else.
//
// It relies on one property of a valid track: the straight line between the
// centres of consecutive gates is drivable (no barrier across it). The
// built-in tracks have it, and the OBJ import convention asks for it.
#pragma once

#include "jetrace/ai/road_profile.hpp"
#include "jetrace/core/world.hpp"

#include <cstddef>
#include <optional>

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
    explicit Course(const Scene& scene, const RoadProbe& probe = {})
        : scene_(&scene), road_(RoadProfile::build(scene.track, scene.grid, probe)) {}

    const Scene& scene() const { return *scene_; }
    const RoadProfile& road() const { return road_; }

private:
    const Scene* scene_;
    RoadProfile road_;
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

/// The input the AI gives car `slot` for the next tick.
Input drive(const Course& course, const WorldState& state, int slot, const DriverSkill& skill = {});

}  // namespace jetrace
