// UniformGrid's walks over the cells of a box: for_each_cell, and the parts
// of collect_overlapping, where the chunk boxes (ChunkBoxes) drop most
// pairs 16 at a time and spare the tests along the axes where a chunk is
// inside the query. Included only by jetrace/core/uniform_grid.hpp, at its end.
#include <algorithm>
#include <cstdint>
#include <vector>

namespace jetrace {

template <class V>
bool UniformGrid::for_each_cell(const Aabb& box, const V& visit) const {
    CellRange q;
    if (!cell_range(box, q)) return true;
    const std::uint64_t span = u64(q.hi[0] - q.lo[0] + 1) * u64(q.hi[1] - q.lo[1] + 1) * u64(q.hi[2] - q.lo[2] + 1);
    if (span > u64(empty_)) {
        const std::uint64_t dx = u64(dims_[0]), dy = u64(dims_[1]);
        for (std::uint32_t c = 0; c < empty_; ++c) {
            const std::uint64_t key = cells_[c].key();
            const auto x = static_cast<std::int32_t>(key % dx);
            const auto y = static_cast<std::int32_t>((key / dx) % dy);
            const auto z = static_cast<std::int32_t>(key / dx / dy);
            if (x < q.lo[0] || x > q.hi[0] || y < q.lo[1] || y > q.hi[1] || z < q.lo[2] || z > q.hi[2]) continue;
            if (!visit(c, q, x, y, z)) return false;
        }
        return true;
    }
    for (std::int32_t z = q.lo[2]; z <= q.hi[2]; ++z) {
        for (std::int32_t y = q.lo[1]; y <= q.hi[1]; ++y) {
            const std::uint64_t row = (u64(z) * u64(dims_[1]) + u64(y)) * u64(dims_[0]);
            for (std::int32_t x = q.lo[0]; x <= q.hi[0]; ++x) {
                if (!visit(find(row + u64(x)), q, x, y, z)) return false;
            }
        }
    }
    return true;
}

template <class Id>
std::size_t UniformGrid::collect_level(const Aabb& box, std::vector<std::uint32_t>& out, std::size_t n,
                                       const Id& id) const {
    const ChunkBoxes::Query cq = chunks_.query(box);
    for_each_cell(box, [&](std::uint32_t c, const CellRange&, std::int32_t, std::int32_t, std::int32_t) {
        n = collect_cell(c, box, cq, out, n, id);
        return true;
    });
    return n;
}

template <class Id>
std::size_t UniformGrid::collect_cell(std::uint32_t c, const Aabb& box, const ChunkBoxes::Query& cq,
                                      std::vector<std::uint32_t>& out, std::size_t n, const Id& id) const {
    const std::uint32_t begin = cells_[c].begin, end = cells_[c + 1].begin;
    if (out.size() < n + (end - begin)) out.resize(std::max<std::size_t>(2 * out.size(), n + (end - begin) + 64));
    std::uint32_t* at = out.data();
    // A cell of fewer pairs than a chunk (most cells of a coarse mesh) is
    // tested pair by pair: its chunks also hold other cells' pairs.
    if (end - begin < ChunkBoxes::kLength) return collect_along<7>(begin, end, box, at, n, id);
    for (std::uint64_t k = begin; k < end;) {
        const std::uint64_t chunk = k >> ChunkBoxes::kShift;
        const std::uint64_t chunk_end = std::min<std::uint64_t>((chunk + 1) << ChunkBoxes::kShift, end);
        const ChunkBoxes::Verdict v = chunks_.classify(chunk, cq);
        if (!v.none) {
            const auto from = static_cast<std::uint32_t>(k), to = static_cast<std::uint32_t>(chunk_end);
            // One loop for each set of axes to test (a branch per chunk, not
            // per pair and axis).
            switch (v.untested) {
                case 0: n = collect_along<0>(from, to, box, at, n, id); break;
                case 1: n = collect_along<1>(from, to, box, at, n, id); break;
                case 2: n = collect_along<2>(from, to, box, at, n, id); break;
                case 3: n = collect_along<3>(from, to, box, at, n, id); break;
                case 4: n = collect_along<4>(from, to, box, at, n, id); break;
                case 5: n = collect_along<5>(from, to, box, at, n, id); break;
                case 6: n = collect_along<6>(from, to, box, at, n, id); break;
                default: n = collect_along<7>(from, to, box, at, n, id); break;
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
