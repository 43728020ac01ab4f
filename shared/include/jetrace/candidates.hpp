// The triangles near a car, at two levels: those gathered from the grid
// around it (and ahead of it), and among them those near where it is now.
#pragma once

#include "jetrace/box_columns.hpp"
#include "jetrace/geometry.hpp"
#include "jetrace/math.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace jetrace {

/// Slack added to every bounding-box test of a candidate (unit: m), so that
/// rounding can never make a box test reject a triangle the exact distance
/// test would accept. Far below the position quantum (1/1024 m).
inline constexpr double kBoxSlack_m = 1e-6;

/// Extra reach of a focus beyond the reach it was made for (unit: m), so
/// that one focus serves the pushes of a step and often the next step.
inline constexpr double kFocusMargin_m = 0.75;

/// The triangles near a car: gathered, then reused by the following steps
/// and every push-out pass while the car stays inside the gathered region.
/// Each comes with its bounding box, so the narrow phase skips a far one
/// by its distance to the box. The vectors are scratch owned by the caller (no
/// allocation once warm).
///
/// A gather covers the region the car will cross in the next steps, so over
/// a dense mesh it holds hundreds of triangles while a car touches a few.
/// The scans at a point (next_touching) therefore go through a focus: the
/// places of the candidates whose boxes lie within a reach of one centre,
/// made by one scan of every box and kept while the scans' spheres stay
/// inside it. A focus only skips boxes the exact test would reject, so what
/// a scan finds never depends on where the focus was made.
struct Candidates {
    /// Ascending triangle indices whose bounds overlap `region`.
    std::vector<std::uint32_t> triangles;
    /// Bounds of each, in the same order.
    std::vector<Aabb> boxes;
    /// The box they were gathered for.
    Aabb region;
    /// Displacement the car will make over the next few steps at its
    /// current velocity (unit: m; set each step): a gather also covers the
    /// region ahead, so one gather serves those steps.
    Vec3 lookahead{0, 0, 0};
    bool all = false;  // brute force: every triangle
    /// A gather's scratch: what the grid found (index << 32 | place) and
    /// the bounds of each, before they are ordered.
    std::vector<std::uint64_t> gathered_keys;
    std::vector<Aabb> gathered_boxes;

    /// Empties the list (before a gather): the focus goes with it.
    void clear() {
        triangles.clear();
        boxes.clear();
        columns_.clear();
        focus_.reach_m = -1.0;
    }

    /// True if a sphere of `radius_m` at `p` is inside the gathered region.
    bool covers(const Vec3& p, double radius_m) const {
        if (all) return true;
        return p.x() - radius_m >= region.min.x() && p.x() + radius_m <= region.max.x() &&
               p.y() - radius_m >= region.min.y() && p.y() + radius_m <= region.max.y() &&
               p.z() - radius_m >= region.min.z() && p.z() + radius_m <= region.max.z();
    }
    /// False if the k-th candidate's box is farther than `reach_m` from `p`
    /// (the distance from `p` to the box, a lower bound of the distance to
    /// the triangle inside it): the triangle cannot come within `reach_m`
    /// of `p`. A car over dense ground passes the per-axis test
    /// (may_reach_along_axes) for every triangle under its sphere's square
    /// shadow; this one only for those under the part within reach.
    bool may_touch(std::size_t k, const Vec3& p, double reach_m) const {
        if (all) return true;
        return box_within(boxes[k], p.x(), p.y(), p.z(), square(reach_m + kBoxSlack_m));
    }
    /// The first candidate from the k-th on that may_touch(p, reach_m)
    /// accepts, or the candidate count if none; k itself under brute force.
    /// Scans the focus around p (made again if it does not hold the sphere
    /// of reach_m around p), so the same in every case as a scan of every
    /// box from k on.
    std::size_t next_touching(std::size_t k, const Vec3& p, double reach_m) const {
        if (all) return k;
        if (!focused_on(p, reach_m)) refocus(p, reach_m + kFocusMargin_m);
        const std::vector<std::uint32_t>& near = focus_.places;
        const auto from = std::lower_bound(near.begin(), near.end(), static_cast<std::uint32_t>(k));
        const std::size_t j = focus_.boxes.first_within(static_cast<std::size_t>(from - near.begin()), p,
                                                        square(reach_m + kBoxSlack_m));
        return j < near.size() ? near[j] : boxes.size();
    }
    /// False if the k-th candidate's box is farther than `reach_m` from `p`
    /// along an axis: it cannot come within `reach_m` of `p`. The sweep's
    /// test (its hits are not decided by a closest distance alone).
    bool may_reach_along_axes(std::size_t k, const Vec3& p, double reach_m) const {
        if (all) return true;
        const Aabb& b = boxes[k];
        const double h = reach_m + kBoxSlack_m;
        return p.x() + h >= b.min.x() && p.x() - h <= b.max.x() && p.y() + h >= b.min.y() &&
               p.y() - h <= b.max.y() && p.z() + h >= b.min.z() && p.z() - h <= b.max.z();
    }
    /// Candidates in the current focus (for the benchmark's figures).
    std::size_t focus_size() const { return focus_.places.size(); }

private:
    static double square(double v) { return v * v; }
    // True if box `b` is within sqrt(h2) of (px, py, pz). A NaN in p makes
    // the sum NaN and the test false, as on every axis of the per-axis test.
    static bool box_within(const Aabb& b, double px, double py, double pz, double h2) {
        const double dx = std::max(std::max(b.min.x() - px, px - b.max.x()), 0.0);
        const double dy = std::max(std::max(b.min.y() - py, py - b.max.y()), 0.0);
        const double dz = std::max(std::max(b.min.z() - pz, pz - b.max.z()), 0.0);
        return dx * dx + dy * dy + dz * dz <= h2;
    }
    // True if every box within reach_m of p is in the focus: the box's
    // distance from the focus centre is at most its distance from p plus
    // |p - centre|, which must then be within the focus's reach (with 1e-6 m
    // to spare for the rounding of both distances).
    bool focused_on(const Vec3& p, double reach_m) const {
        const double spare = focus_.reach_m - reach_m - kBoxSlack_m;
        if (!(spare >= 0.0)) return false;  // also a NaN p or reach
        return (p - focus_.center).squaredNorm() <= spare * spare;
    }
    // Makes the focus: the places of every box within reach_m of `center`.
    void refocus(const Vec3& center, double reach_m) const {
        if (columns_.size() != boxes.size()) {  // the first focus since the gather
            columns_.clear();
            for (const Aabb& b : boxes) columns_.push(b);
        }
        focus_.places.clear();
        focus_.boxes.clear();
        focus_.center = center;
        focus_.reach_m = reach_m;
        columns_.for_each_within(center, square(reach_m + kBoxSlack_m), [&](std::size_t k) {
            focus_.places.push_back(static_cast<std::uint32_t>(k));
            focus_.boxes.push(boxes[k]);
        });
        if (!(reach_m >= 0.0)) focus_.reach_m = -1.0;  // a NaN centre or reach: never reused
    }

    // A cache of the scans: ascending candidate places whose boxes are
    // within reach_m (+ the slack) of `center`; none while reach_m < 0.
    struct Focus {
        std::vector<std::uint32_t> places;
        BoxColumns boxes;  // the boxes of those places, in the same order
        Vec3 center{0, 0, 0};
        double reach_m = -1.0;
    };
    mutable Focus focus_;
    // Every box by column, made by the first focus after a gather.
    mutable BoxColumns columns_;
};

}  // namespace jetrace
