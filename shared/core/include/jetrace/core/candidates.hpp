// A car's candidate triangles: what the resolver scans, pass after pass.
#pragma once

#include "jetrace/core/geometry.hpp"
#include "jetrace/core/packed_boxes.hpp"

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
/// by its distance to the box; each run of kRunLength consecutive
/// candidates with the box around theirs, and each group of kRunLength
/// runs with the box around those, so a scan skips a far run or group in
/// one test. Boxes are packed eight to a test (PackedBoxes): a query tests
/// a group's eight run boxes at once, then a run's eight boxes at once. The
/// vectors are scratch owned by the caller (no allocation once warm).
struct Candidates {
    /// Candidates per run (see `runs`): the boxes of one packed test.
    static constexpr std::size_t kRunShift = 3;
    static constexpr std::size_t kRunLength = std::size_t{1} << kRunShift;
    /// Candidates per group (see `groups`): kRunLength runs, one packed test.
    static constexpr std::size_t kGroupShift = 2 * kRunShift;
    static_assert(kRunLength == PackedBoxes::kLanes);

    /// Ascending triangle indices whose boxes (the grid's, each containing
    /// the triangle's bounds: UniformGrid::box) overlap `region`.
    std::vector<std::uint32_t> triangles;
    /// Those boxes, in the same order.
    PackedBoxes boxes;
    /// Run j: the box around boxes j * kRunLength to (j + 1) * kRunLength - 1
    /// (the last run may be shorter). Meshes list their triangles with
    /// neighbours near each other (strips, patches, rows), so a run's box is
    /// small and a car over dense ground is within reach of few runs. Padded
    /// with empty boxes to whole groups.
    PackedBoxes runs;
    /// The same over groups of kRunLength runs, tested before their runs.
    PackedBoxes groups;
    /// The box they were gathered for.
    Aabb region;
    /// Displacement the car will make over the next few steps at its
    /// current velocity (unit: m; set by the step when it gathers, and kept
    /// for the gathers the push-out may make later in that step and the
    /// next): a gather also covers the region ahead, so one gather serves
    /// those steps.
    Vec3 lookahead{0, 0, 0};
    /// Steps that have used this region since it was gathered (a gather
    /// sets 0; the step's gather check counts, and sizes the next
    /// look-ahead by it; unit: steps).
    std::uint32_t steps_served = 0;
    bool all = false;  // brute force: every triangle
    /// The gather's scratch (kept to keep its capacity).
    MergeScratch merge_scratch;

    /// Frames of the triangles the scans test (see FrameCache), kept
    /// across gathers while the candidates come from the same `track`.
    mutable FrameCache frames;
    const Track* track = nullptr;

    /// The end of a gather: fills `boxes` from box_of(i) (the FloatBox of
    /// triangle i, for each of `triangles`), and `runs` and `groups` around
    /// them (in floats: exact), in one pass.
    template <class BoxOf>
    void finish_gather(BoxOf&& box_of) {
        const std::size_t n = triangles.size();
        const std::size_t run_count = (n + kRunLength - 1) >> kRunShift;
        const std::size_t group_count = (run_count + kRunLength - 1) >> kRunShift;
        boxes.reset(n);
        runs.reset(run_count);  // padded to whole groups
        groups.reset(group_count);
        found.resize(n + kRunLength);  // a query writes whole runs
        FloatBox run, group;
        for (std::size_t k = 0; k < n; ++k) {
            const FloatBox& b = box_of(triangles[k]);
            boxes.set(k, b);
            if (k % kRunLength == 0) {
                run = b;
            } else {
                run.expand(b);
            }
            if (k % kRunLength != kRunLength - 1 && k + 1 != n) continue;
            const std::size_t r = k >> kRunShift;  // the run just ended
            runs.set(r, run);
            if (r % kRunLength == 0) {
                group = run;
            } else {
                group.expand(run);
            }
            if (r % kRunLength == kRunLength - 1 || k + 1 == n) groups.set(r >> kRunShift, group);
        }
    }

    /// True if a sphere of `radius_m` at `p` is inside the gathered region.
    /// All six comparisons are made (no branch on each: a step asks
    /// several times, and the answer is almost always yes).
    bool covers(const Vec3& p, double radius_m) const {
        if (all) return true;
        const bool x = (p.x() - radius_m >= region.min.x()) & (p.x() + radius_m <= region.max.x());
        const bool y = (p.y() - radius_m >= region.min.y()) & (p.y() + radius_m <= region.max.y());
        const bool z = (p.z() - radius_m >= region.min.z()) & (p.z() + radius_m <= region.max.z());
        return x & y & z;
    }
    /// False if the k-th candidate's box is farther than `reach_m` from `p`
    /// (the distance from `p` to the box, a lower bound of the distance to
    /// the triangle inside it; PackedBoxes::within): the triangle cannot
    /// come within `reach_m` of `p`. A car over dense ground passes the
    /// per-axis test (may_reach_along_axes) for every triangle under its
    /// sphere's square shadow; this one only for those under the part
    /// within reach.
    bool may_touch(std::size_t k, const Vec3& p, double reach_m) const { return may_touch(k, box_query(p, reach_m)); }
    /// The same for a query made once for many candidates.
    bool may_touch(std::size_t k, const BoxQuery& q) const { return all || boxes.within(k, q); }
    /// A point and reach to test the candidates' boxes against.
    BoxQuery box_query(const Vec3& p, double reach_m) const { return boxes.query(p, reach_m); }
    /// Every candidate from the k-th on that may_touch(p, reach_m) accepts,
    /// in ascending order: their places are found[0, count), count
    /// returned (valid until the next query). Not for brute force. A group
    /// or run whose box is beyond reach is skipped whole: no box inside it
    /// is nearer, so the answer is exactly the one-by-one test's.
    std::size_t touching_from(std::size_t k, const Vec3& p, double reach_m) const;

    /// What touching_from() returns (sized at the gather, with room for a
    /// whole run past the last candidate: a query stores each tested run's
    /// places without a branch, advancing past those that pass).
    mutable std::vector<std::uint32_t> found;

    /// False if the k-th candidate's box is farther than `reach_m` from `p`
    /// along an axis: it cannot come within `reach_m` of `p`. The sweep's
    /// test (its hits are not decided by a closest distance alone).
    bool may_reach_along_axes(std::size_t k, const BoxQuery& q) const { return all || boxes.within_along_axes(k, q); }
};

}  // namespace jetrace
