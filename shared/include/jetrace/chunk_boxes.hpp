// Boxes around runs of a grid level's triangle-cell pairs, so that a query
// keeps or drops most pairs a run at a time (UniformGrid::collect_overlapping).
#pragma once

#include "jetrace/geometry.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace jetrace {

/// For each chunk of kLength consecutive pairs of a grid level (its item
/// list, cell after cell; a chunk may span two cells), the box around
/// their triangles' boxes, in 16-bit integers per bound: each axis of the
/// box around every box of the level is divided into kUnits steps, and
/// each bound is rounded outward by more than a step, so the chunk's box
/// holds every box in it (12 bytes a chunk: 0.75 bytes a pair).
///
/// A query tells, for a chunk, whether no box in it can overlap the query
/// box, or along which axes its boxes may not (the others need no test):
/// along none of them, every box in it does. The answers are certain (the
/// rounding of the frame's arithmetic is far below the step it rounds
/// by), so a caller that keeps or drops a chunk by them, and tests the
/// rest along those axes, keeps exactly the pairs whose own boxes overlap.
class ChunkBoxes {
public:
    static constexpr std::uint32_t kShift = 4;
    static constexpr std::uint32_t kLength = std::uint32_t{1} << kShift;
    /// Steps of the frame along each axis.
    static constexpr double kUnits = 65532.0;

    /// Over the pairs `items` (triangle indices) with their boxes `boxes`.
    void build(const std::vector<std::uint32_t>& items, const std::vector<FloatBox>& boxes);

    /// A query box in the frame's steps.
    struct Query {
        double lo[3] = {0, 0, 0};
        double hi[3] = {0, 0, 0};
    };
    Query query(const Aabb& box) const;

    /// What chunk c's box tells of its boxes against the query's box.
    struct Verdict {
        bool none = false;  ///< none of them overlaps it
        /// Otherwise, bit i set if the chunk's box crosses the query box's
        /// bounds along axis i: its boxes overlap the query's along every
        /// other axis, so only these need testing (0: all of them overlap).
        std::uint32_t crossed = 0;
    };
    Verdict classify(std::size_t c, const Query& q) const {
        const Bounds& b = chunks_[c];
        Verdict v;
        for (int i = 0; i < 3; ++i) {
            const double lo = b[static_cast<std::size_t>(i)], hi = b[static_cast<std::size_t>(i + 3)];
            // Half a step of room: the query's bounds round by far less.
            v.none = v.none || hi < q.lo[i] - 0.5 || lo > q.hi[i] + 0.5;
            const bool inside = lo >= q.lo[i] + 0.5 && hi <= q.hi[i] - 0.5;  // false for NaN
            v.crossed |= inside ? 0u : 1u << i;
        }
        return v;
    }

    std::size_t memory_bytes() const { return chunks_.size() * sizeof(Bounds); }

private:
    using Bounds = std::array<std::uint16_t, 6>;  // lo x, y, z, hi x, y, z (steps)
    double origin_[3] = {0, 0, 0};
    double steps_per_m_[3] = {0, 0, 0};
    std::vector<Bounds> chunks_;
};

}  // namespace jetrace
