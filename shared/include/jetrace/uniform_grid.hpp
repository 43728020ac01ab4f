// A dense 3D uniform grid over a track's triangles.
//
// Triangles are bucketed by their bounding box; a query box (the car's) is
// bucketed by the same function (cell_range). Each candidate is reported
// once per query without allocating and without mutable state: a triangle
// met in cell C is reported only if C is the lowest cell of the overlap of
// the query's cell range and the triangle's cell range ("owner cell").
//
// Cell size rule (see cell_size_for): the edge is the larger of
//   - 4 car radii (a car's box, 2r + skin wide, then touches at most 8 and
//     on average about 2 cells), and
//   - the edge that keeps the cell count at or below kMaxCells
//     (cube root of bounds volume / kMaxCells).
#pragma once

#include "jetrace/geometry.hpp"

#include <cstdint>
#include <vector>

namespace jetrace {

struct CellRange {
    std::int32_t lo[3];
    std::int32_t hi[3];
};

class UniformGrid {
public:
    /// Upper bound on the number of cells (memory: 4 bytes per cell plus
    /// 4 bytes per triangle-cell pair).
    static constexpr std::int64_t kMaxCells = std::int64_t{1} << 21;

    /// The documented rule for the cell edge (unit: m).
    static double cell_size_for(const Aabb& bounds, double car_radius_m);

    UniformGrid() = default;
    /// Builds over `triangles` with `cell_size_m` (0 = cell_size_for).
    UniformGrid(const std::vector<Triangle>& triangles, const Aabb& bounds, double car_radius_m,
                double cell_size_m = 0.0);

    /// The cells a box covers (clamped to the grid). Returns false if the box
    /// misses the grid entirely.
    bool cell_range(const Aabb& box, CellRange& out) const;

    /// Calls f(triangle_index) once for every triangle whose bucket overlaps
    /// `box`, in ascending cell order (x fastest, then y, then z).
    template <class F>
    void for_each_candidate(const Aabb& box, F&& f) const {
        CellRange q;
        if (!cell_range(box, q)) return;
        for (std::int32_t z = q.lo[2]; z <= q.hi[2]; ++z) {
            for (std::int32_t y = q.lo[1]; y <= q.hi[1]; ++y) {
                for (std::int32_t x = q.lo[0]; x <= q.hi[0]; ++x) {
                    const std::int64_t cell = index(x, y, z);
                    const std::uint32_t begin = cell_start_[cell];
                    const std::uint32_t end = cell_start_[cell + 1];
                    for (std::uint32_t k = begin; k < end; ++k) {
                        const std::uint32_t tri = items_[k];
                        const CellRange& r = tri_cells_[tri];
                        // Owner cell: lowest cell of the two ranges' overlap.
                        const std::int32_t ox = r.lo[0] > q.lo[0] ? r.lo[0] : q.lo[0];
                        const std::int32_t oy = r.lo[1] > q.lo[1] ? r.lo[1] : q.lo[1];
                        const std::int32_t oz = r.lo[2] > q.lo[2] ? r.lo[2] : q.lo[2];
                        if (ox == x && oy == y && oz == z) f(tri);
                    }
                }
            }
        }
    }

    double cell_size_m() const { return cell_; }
    std::int64_t cell_count() const { return std::int64_t{dims_[0]} * dims_[1] * dims_[2]; }
    std::size_t entry_count() const { return items_.size(); }
    /// Bytes held by the grid's arrays.
    std::size_t memory_bytes() const;
    const std::int32_t* dims() const { return dims_; }

private:
    std::int64_t index(std::int32_t x, std::int32_t y, std::int32_t z) const {
        return (std::int64_t{z} * dims_[1] + y) * dims_[0] + x;
    }
    std::int32_t coord(double v, int axis) const;

    Vec3 origin_{0, 0, 0};
    double cell_ = 1.0;
    double inv_cell_ = 1.0;
    std::int32_t dims_[3] = {1, 1, 1};
    Aabb bounds_;
    std::vector<std::uint32_t> cell_start_;  // CSR offsets, cell_count()+1
    std::vector<std::uint32_t> items_;       // triangle indices, ascending per cell
    std::vector<CellRange> tri_cells_;       // each triangle's bucket range
};

}  // namespace jetrace
