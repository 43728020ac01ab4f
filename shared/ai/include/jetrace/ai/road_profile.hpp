// Road heights along a track's route (the closed polyline through its gate
// centres), sampled once when the scene is made: what the driving AI reads
// to see a crest ahead without searching the grid on every tick.
#pragma once

#include "jetrace/core/track.hpp"
#include "jetrace/core/uniform_grid.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace jetrace {

/// What counts as road under the route, and how densely it is sampled.
struct RoadProbe {
    /// Spacing of the samples along each leg, in the ground plan (unit: m).
    double spacing_m = 1.0;
    /// Road slopes like one: its unit normal's |y| at least this, the face
    /// wound either way (unit: cosine).
    double min_up = 0.7;
    /// The road is looked for from this far above the route line to this
    /// far below it (unit: m; each at most 32, what the profile stores).
    double above_m = 3.0;
    double below_m = 15.0;
};

class RoadProfile {
public:
    /// Resolution of the stored heights (unit: m).
    static constexpr double kResolution_m = 1e-3;

    RoadProfile() = default;

    /// Samples every leg of `track`'s route through `grid` (built over
    /// `track.triangles`). Leg k runs from gate k-1 to gate k (gate 0's
    /// leg from the last gate).
    static RoadProfile build(const Track& track, const UniformGrid& grid, const RoadProbe& probe = {});

    /// Height of the road under the point a fraction `t` (0..1) of the way
    /// along leg `leg` (any integer: taken modulo the gate count), linear
    /// between the two samples around it (unit: m). False where either has
    /// no road.
    bool height(std::int32_t leg, double t, double& y) const;

    /// True if an obstacle stands on the route near the point a fraction
    /// `t` along leg `leg`: a top more than a step (1.25 m) above the road
    /// a car drives on there, in either of the two samples around it.
    bool obstacle(std::int32_t leg, double t) const;

    /// height() and obstacle() at one point, located once (16 bytes: a
    /// call returns it in two registers).
    struct Sample {
        double y = 0;  // valid if has_height (unit: m)
        bool has_height = false;
        bool obstacle = false;
    };
    Sample sample(std::int32_t leg, double t) const;

    /// The one height sample() gives everywhere on leg `leg` (any integer,
    /// as above) if the leg is level: the route line flat (its two gates'
    /// centres at one height), the road found at one offset from it at
    /// every sample, and no obstacle (unit: m). NaN otherwise, which equals
    /// nothing: legs that compare equal here give equal heights all along.
    double level_height(std::int32_t leg) const;

    std::size_t legs() const { return legs_.size(); }
    std::size_t memory_bytes() const;

private:
    static constexpr std::int16_t kNone = INT16_MIN;
    // One sample: the road's height above the route line in kResolution_m
    // (kNone where there is no road), and 1 where an obstacle stands
    // (obstacle()).
    struct Point {
        std::int16_t offset = kNone;
        std::uint8_t obstacle = 0;
    };
    // Leg k (all a sample() reads of it, together): its samples are
    // points_[first .. first + intervals], the first at its start gate and
    // the last at its end gate; the route line runs from height y0 (gate
    // k - 1's centre) to y1 (gate k's).
    struct Leg {
        std::uint32_t first = 0;
        std::uint32_t intervals = 1;
        double y0 = 0;
        double y1 = 0;
    };
    // level_height() of leg `l`, from its samples.
    double level_of(const Leg& l) const;

    std::vector<Leg> legs_;
    std::vector<Point> points_;
    // The level_height() of each leg, in leg order.
    std::vector<double> level_;
};

}  // namespace jetrace
