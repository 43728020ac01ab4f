// Boxes around runs of a grid level's triangle-cell pairs, so that a query
// drops most pairs a run at a time (UniformGrid::collect_overlapping).
#pragma once

#include "jetrace/core/geometry.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace jetrace {

/// For each chunk of kLength consecutive pairs of a grid level (its item
/// list, cell after cell; a chunk may span two cells), the box around
/// their triangles' boxes, in 16-bit integers per bound (12 bytes a chunk:
/// 0.75 bytes a pair). Each axis of the box around every box of the level
/// is divided into kUnits steps; a bound goes to steps through one
/// function, monotonic (a rounded difference, then a rounded product by a
/// positive constant), so bounds keep their order in steps, and a chunk's
/// lower bound is stored at least one step below its boxes' (floor, minus
/// one, clamped at 0) and its upper bound at least one step above (ceil,
/// plus one).
///
/// A query goes to steps through the same function. A chunk is called
/// outside the query box along an axis, or inside it, only with half a
/// step to spare: equal values in steps (rounding can merge bounds a step
/// apart, and the clamp at 0 can raise a lower bound to the query's) never
/// decide. So the verdicts are certain: a caller that drops the chunks
/// found outside and tests the others only along the axes where they are
/// not found inside keeps exactly the pairs whose own boxes overlap.
///
/// A level with a box that is not finite (validated tracks have none) gets
/// no verdicts: every chunk is tested along every axis.
class ChunkBoxes {
public:
    static constexpr std::uint32_t kShift = 4;
    static constexpr std::uint32_t kLength = std::uint32_t{1} << kShift;
    /// Steps of the frame along each axis.
    static constexpr double kUnits = 65532.0;

    /// Over the pairs `items` (triangle indices) with their boxes `boxes`.
    void build(const std::vector<std::uint32_t>& items, const std::vector<FloatBox>& boxes);

    /// A query box in the frame's steps, with the half step to spare
    /// already added or taken away.
    struct Query {
        double below_lo[3] = {0, 0, 0};  ///< the lower bound less half a step
        double above_lo[3] = {0, 0, 0};  ///< the lower bound plus half a step
        double below_hi[3] = {0, 0, 0};  ///< the upper bound less half a step
        double above_hi[3] = {0, 0, 0};  ///< the upper bound plus half a step
    };
    Query query(const Aabb& box) const;

    /// What chunk c's box tells of its boxes against the query's box.
    struct Verdict {
        bool none = false;  ///< none of them overlaps it
        /// Otherwise, bit i set unless the chunk's box is inside the query
        /// box along axis i: its boxes overlap the query's along every axis
        /// whose bit is clear, so only the others need testing (0: all of
        /// them overlap).
        std::uint32_t untested = 0;
    };
    Verdict classify(std::size_t c, const Query& q) const {
        const Bounds& b = chunks_[c];
        Verdict v;
        for (int i = 0; i < 3; ++i) {
            const double lo = b[static_cast<std::size_t>(i)], hi = b[static_cast<std::size_t>(i + 3)];
            v.none = v.none || hi < q.below_lo[i] || lo > q.above_hi[i];  // false for NaN
            const bool inside = lo >= q.above_lo[i] && hi <= q.below_hi[i];  // false for NaN
            v.untested |= inside ? 0u : 1u << i;
        }
        return v;
    }

    std::size_t memory_bytes() const { return chunks_.size() * sizeof(Bounds); }

private:
    using Bounds = std::array<std::uint16_t, 6>;  // lo x, y, z, hi x, y, z (steps)
    double origin_[3] = {0, 0, 0};
    double steps_per_m_[3] = {0, 0, 0};  // NaN: no verdicts
    std::vector<Bounds> chunks_;
};

}  // namespace jetrace
