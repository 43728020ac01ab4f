// UniformGrid::collect_overlapping's work in one cell: the chunk boxes
// (ChunkBoxes) drop most pairs 16 at a time and spare the tests of the
// axes along which a chunk lies inside the query. Included by
// jetrace/uniform_grid.hpp.
#pragma once

#include "jetrace/uniform_grid.hpp"

namespace jetrace {

template <class Id>
std::size_t UniformGrid::collect_cell(std::uint32_t c, const Aabb& box, const ChunkBoxes::Query& cq,
                                      std::vector<std::uint32_t>& out, std::size_t n, const Id& id) const {
    const std::uint32_t begin = cells_[c].begin, end = cells_[c + 1].begin;
    if (out.size() < n + (end - begin)) out.resize(std::max<std::size_t>(2 * out.size(), n + (end - begin) + 64));
    std::uint32_t* at = out.data();
    if (end - begin < ChunkBoxes::kLength) {  // fewer than a chunk: no chunk box decides them
        return collect_along<7>(begin, end, box, at, n, id);
    }
    for (std::uint32_t k = begin; k < end;) {
        const std::uint32_t chunk = k >> ChunkBoxes::kShift;
        const std::uint32_t chunk_end = std::min((chunk + 1) << ChunkBoxes::kShift, end);
        const ChunkBoxes::Verdict v = chunks_.classify(chunk, cq);
        if (!v.none) {
            // One loop for each set of axes to test (a branch per chunk, not
            // per pair and axis).
            switch (v.crossed) {
                case 0: n = collect_along<0>(k, chunk_end, box, at, n, id); break;
                case 1: n = collect_along<1>(k, chunk_end, box, at, n, id); break;
                case 2: n = collect_along<2>(k, chunk_end, box, at, n, id); break;
                case 3: n = collect_along<3>(k, chunk_end, box, at, n, id); break;
                case 4: n = collect_along<4>(k, chunk_end, box, at, n, id); break;
                case 5: n = collect_along<5>(k, chunk_end, box, at, n, id); break;
                case 6: n = collect_along<6>(k, chunk_end, box, at, n, id); break;
                default: n = collect_along<7>(k, chunk_end, box, at, n, id); break;
            }
        }
        k = chunk_end;
    }
    return n;
}

template <unsigned kAxes, class Id>
std::size_t UniformGrid::collect_along(std::uint32_t from, std::uint32_t to, const Aabb& box, std::uint32_t* at,
                                       std::size_t n, const Id& id) const {
    // Every one stored, the end moved past it only if kept (no branch on a
    // test that goes either way). Along an axis, the test of Aabb::overlaps.
    for (std::uint32_t i = from; i < to; ++i) {
        const std::uint32_t t = items_[i];
        at[n] = id(t);
        const FloatBox& b = boxes_[t];
        bool keep = true;
        if constexpr ((kAxes & 1u) != 0) keep = keep && b.lo[0] <= box.max.x() && box.min.x() <= b.hi[0];
        if constexpr ((kAxes & 2u) != 0) keep = keep && b.lo[1] <= box.max.y() && box.min.y() <= b.hi[1];
        if constexpr ((kAxes & 4u) != 0) keep = keep && b.lo[2] <= box.max.z() && box.min.z() <= b.hi[2];
        n += keep ? 1 : 0;
    }
    return n;
}

}  // namespace jetrace
