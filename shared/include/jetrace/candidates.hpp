// A car's candidate triangles: what the resolver scans, pass after pass.
#pragma once

#include "jetrace/geometry.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace jetrace {

struct Track;

/// Each triangle's TriangleFrame once computed, for the triangles a car
/// tests step after step: the frame is what a closest-point test costs
/// (four square roots and twelve divisions). Direct-mapped by triangle
/// index and kept across gathers; a cache of a pure function of the
/// triangle, so it never changes a result.
class FrameCache {
public:
    static constexpr int kSlotBits = 6;
    static constexpr std::size_t kSlots = std::size_t{1} << kSlotBits;

    FrameCache() { clear(); }
    void clear() { keys_.fill(kNone); }
    /// The frame of triangle `index` (`t`, not degenerate).
    const TriangleFrame& get(std::uint32_t index, const Triangle& t) {
        // Fibonacci hashing spreads neighbouring indices over the slots.
        // Some strides share a slot (about one in 32: a grid mesh of such
        // a row length, or more than 64 triangles in use, evicts frames
        // that are then computed again), which costs time, never a result.
        const std::size_t slot = static_cast<std::uint32_t>(index * 0x9E3779B1u) >> (32 - kSlotBits);
        if (keys_[slot] != index) {
            frames_[slot] = TriangleFrame::of(t);
            keys_[slot] = index;
        }
        return frames_[slot];
    }

private:
    static constexpr std::uint32_t kNone = ~std::uint32_t{0};  // above any triangle index
    std::array<std::uint32_t, kSlots> keys_;
    std::array<TriangleFrame, kSlots> frames_;
};

/// Slack added to every bounding-box test of a candidate (unit: m), so that
/// rounding can never make a box test reject a triangle the exact distance
/// test would accept. Far below the position quantum (1/1024 m).
inline constexpr double kBoxSlack_m = 1e-6;

/// Squared distance from `p` to box `b` (0 inside), each axis's gap
/// rounded as computed; a NaN in `p` makes it NaN (and every `<=` false).
/// Monotonic in the box: a box containing `b` is never farther.
inline double box_distance2(const Aabb& b, double px, double py, double pz) {
    const double dx = std::max(std::max(b.min.x() - px, px - b.max.x()), 0.0);
    const double dy = std::max(std::max(b.min.y() - py, py - b.max.y()), 0.0);
    const double dz = std::max(std::max(b.min.z() - pz, pz - b.max.z()), 0.0);
    return dx * dx + dy * dy + dz * dz;
}

/// What the gather's merge of its ascending runs works in (kept between
/// gathers so that a warm gather does not allocate).
struct MergeScratch {
    std::vector<std::uint32_t> values;
    std::vector<std::size_t> starts;
    std::vector<std::size_t> next_starts;
};

/// The triangles near a car: gathered, then reused by the following steps
/// and every push-out pass while the car stays inside the gathered region.
/// Each comes with its bounding box, so the narrow phase skips a far one
/// by its distance to the box, and each run of kRunLength consecutive
/// candidates with the box around theirs, so a scan skips a far run in
/// one test. The vectors are scratch owned by the caller (no allocation
/// once warm).
struct Candidates {
    /// Candidates per run (see `runs`): a power of two.
    static constexpr std::size_t kRunShift = 3;
    static constexpr std::size_t kRunLength = std::size_t{1} << kRunShift;
    /// Candidates per group (see `groups`): a power of two, a multiple of kRunLength.
    static constexpr std::size_t kGroupShift = 6;

    /// Ascending triangle indices whose boxes (the grid's, each containing
    /// the triangle's bounds: UniformGrid::box) overlap `region`.
    std::vector<std::uint32_t> triangles;
    /// Those boxes, in the same order.
    std::vector<Aabb> boxes;
    /// The box around boxes[j * kRunLength] to boxes[(j + 1) * kRunLength - 1]
    /// (the last run may be shorter). Meshes list their triangles with
    /// neighbours near each other (strips, patches, rows), so a run's box is
    /// small and a car over dense ground is within reach of few runs.
    std::vector<Aabb> runs;
    /// The same over runs of 2^kGroupShift candidates, tested first.
    std::vector<Aabb> groups;
    /// The box they were gathered for.
    Aabb region;
    /// Displacement the car will make over the next few steps at its
    /// current velocity (unit: m; set each step): a gather also covers the
    /// region ahead, so one gather serves those steps.
    Vec3 lookahead{0, 0, 0};
    bool all = false;  // brute force: every triangle
    /// The gather's scratch (kept to keep its capacity).
    MergeScratch merge_scratch;

    /// Frames of the triangles the scans test (see FrameCache), kept
    /// across gathers while the candidates come from the same `track`.
    mutable FrameCache frames;
    const Track* track = nullptr;

    /// The end of a gather: fills `boxes` from box_of(i) (the FloatBox of
    /// triangle i, for each of `triangles`), and `runs` and `groups`
    /// around them, in one pass (in floats, exact, then widened to doubles
    /// like the boxes: the same values as the boxes' own min and max).
    template <class BoxOf>
    void finish_gather(BoxOf&& box_of) {
        const std::size_t n = triangles.size();
        boxes.resize(n);
        found.resize(n);
        runs.clear();
        groups.clear();
        constexpr std::size_t kRunsPerGroup = std::size_t{1} << (kGroupShift - kRunShift);
        FloatBox run, group;
        for (std::size_t k = 0; k < n; ++k) {
            const FloatBox& b = box_of(triangles[k]);
            boxes[k] = b.aabb();
            if (k % kRunLength == 0) {
                run = b;
            } else {
                run.expand(b);
            }
            if (k % kRunLength != kRunLength - 1 && k + 1 != n) continue;
            const std::size_t r = k / kRunLength;  // the run just ended
            runs.push_back(run.aabb());
            if (r % kRunsPerGroup == 0) {
                group = run;
            } else {
                group.expand(run);
            }
            if (r % kRunsPerGroup == kRunsPerGroup - 1 || k + 1 == n) groups.push_back(group.aabb());
        }
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
        const double h = reach_m + kBoxSlack_m;
        return box_distance2(boxes[k], p.x(), p.y(), p.z()) <= h * h;
    }
    /// Every candidate from the k-th on that may_touch(p, reach_m) accepts,
    /// in ascending order: their places are found[0, count), count
    /// returned (valid until the next query). Not for brute force. A group
    /// or run whose box is beyond reach is skipped whole: no box inside it
    /// is nearer (box_distance2 is monotonic), so the answer is exactly the
    /// one-by-one test's.
    std::size_t touching_from(std::size_t k, const Vec3& p, double reach_m) const;

    /// What touching_from() returns (sized at the gather, so that a query
    /// writes without a branch on each test).
    mutable std::vector<std::uint32_t> found;

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
};

}  // namespace jetrace
