// A sparse 3D uniform grid over a track's triangles.
//
// Triangles are bucketed by their bounding box; a query box (the car's) is
// bucketed by the same function (cell_range). Each candidate is reported
// once per query without allocating and without mutable state: a triangle
// met in cell C is reported only if C is the lowest cell of the overlap of
// the query's cell range and the triangle's cell range ("owner cell").
//
// Cells are addressed as in a dense grid over the track's bounds
// (dims() cells per axis, coordinates clamped to them; the cell key is the
// dense index x + dims_x * (y + dims_y * z)), but only occupied cells are
// stored:
//   cells_  the occupied cells by ascending key: key and CSR start into
//           items_ (12 bytes; a cell's triangles end where the next cell's
//           start), then one empty cell and an end marker;
//   items_  triangle indices, ascending within a cell;
//   slots_  an open-addressing hash table (linear probing, power-of-two
//           capacity, load <= 0.5) from key to index in cells_;
//   chunks_ the box around each 16 consecutive pairs of items_
//           (ChunkBoxes, 12 bytes: 16-bit bounds), so that a gather drops
//           most pairs 16 at a time and tests fewer axes of the others
//           (collect_overlapping).
// A lookup is one hash, one slot and one cell (a second probe is rare);
// empty cells are not stored, their lookups end on an empty slot, which
// names the empty cell. Everything is built from the (key, triangle) pairs
// sorted by (key, triangle), and the table is filled in ascending key order
// with a fixed hash, so the layout is a pure function of the geometry
// (nothing depends on allocation addresses or insertion history). Memory:
// 4.75 bytes per triangle-cell pair, at most 28 bytes per occupied cell and
// 24 bytes per triangle (see memory_bytes), independent of the bounding
// volume.
//
// Each triangle is bucketed by its box in floats, rounded outward
// (FloatBox, 24 bytes; box()): the grid keeps it, and the owner cell is
// computed from it. A gather reads these boxes, 24 bytes a triangle laid
// out in triangle order, and not the triangles (80 bytes each, far outside
// the caches on a track of millions).
//
// Two levels: a triangle whose box covers more than kLargeCells cells is
// not bucketed in these cells but in a second, coarse grid of the same kind
// (cells kCoarseFactor times as wide, holding only those triangles), which
// every query walks after the fine one. A level's few ground triangles far
// wider than its cells would otherwise make most of the pairs (truck_town:
// 94 % of them in 10 m cells, 219 bytes a triangle; 32 with two levels, at
// the same cost per car-step). for_each_candidate reports every triangle
// bucketed in a box's cells once (its owner cell decides); the gather uses
// collect_overlapping instead, which keeps those whose boxes overlap the
// query, once per cell (repeats possible), and then merges and drops the
// repeats.
//
// Cell size rule (see cell_size_for): the edge is the typical triangle's
// size (the median over the triangles of their box's largest extent),
// clamped between 4 and 16 car radii (10 m and 40 m for r = 2.5 m). A car's
// box (2r + skin wide) then touches at most 8 cells. Cells as large as the
// typical triangle store each triangle in about 2 to 4 cells instead of
// about 20 (the stadium's 35 m squares in 10 m cells), and, measured with
// `jetrace-bench density --cell-m`, cost the step no more. Cells finer
// than 10 m cost more per step on every track measured, the 2 M-triangle
// landscape of 1 m triangles included (5 m cells: 1.07 times 10 m), so the
// edge stays 4 radii on fine meshes. The step's
// results do not depend on the edge (the gather sorts its candidates),
// only its cost and the grid's memory.
// Only two limits can make the edge larger:
//   - the key: each axis holds at most kMaxAxisCells = 2^21 cells (so the
//     key fits 63 bits); a track within kMaxTrackCoordinate_m (1e6 m) needs
//     2e5 cells per axis at 10 m, so this only grows a tiny explicit size or
//     radius (the edge is then multiplied by 1.0625 until every axis fits);
//   - the pair budget: if the triangle-cell pairs would exceed
//     entry_budget(triangles) (32 per triangle on average, or 2^22 in all,
//     whichever is larger), the constructor grows the edge until they fit.
//     Normal tracks are far below it (truck_town: 18 per triangle); it
//     guards against a few huge triangles (a 2,000 km ground quad would be
//     4e10 cells at 10 m).
#pragma once

#include "jetrace/core/chunk_boxes.hpp"
#include "jetrace/core/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace jetrace {

struct CellRange {
    std::int32_t lo[3];
    std::int32_t hi[3];
};

class UniformGrid {
public:
    /// Most cells per axis (so the key, the dense index, stays below 2^63).
    static constexpr std::int32_t kMaxAxisCells = std::int32_t{1} << 21;
    /// The pair budget: at least this many triangle-cell pairs in all...
    static constexpr std::int64_t kMinEntryBudget = std::int64_t{1} << 22;
    /// ...or this many per triangle on average, whichever is larger.
    static constexpr std::int64_t kEntriesPerTriangle = 32;
    static std::int64_t entry_budget(std::size_t triangles);

    /// The rule's bounds on the cell edge (unit: car radii).
    static constexpr double kMinCellRadii = 4.0;
    static constexpr double kMaxCellRadii = 16.0;
    /// The typical triangle's size (unit: m): the median over `triangles`
    /// of their box's largest extent (0 if there are none).
    static double typical_extent_m(const std::vector<Triangle>& triangles);
    /// The documented rule for the cell edge (unit: m): typical_extent_m
    /// clamped to [kMinCellRadii, kMaxCellRadii] car radii, grown only if an
    /// axis of `bounds` would exceed kMaxAxisCells.
    static double cell_size_for(const std::vector<Triangle>& triangles, const Aabb& bounds, double car_radius_m);

    UniformGrid() = default;
    /// Builds over `triangles` with `cell_size_m` (0 = cell_size_for). An
    /// explicit size is grown like the rule's if an axis would exceed
    /// kMaxAxisCells; either is grown if the pairs would exceed the budget.
    UniformGrid(const std::vector<Triangle>& triangles, const Aabb& bounds, double car_radius_m,
                double cell_size_m = 0.0)
        : UniformGrid(triangles, bounds, car_radius_m, cell_size_m, Levels::two) {}

    /// Two levels (the default): a triangle whose box covers more than
    /// kLargeCells cells is kept in a coarse level of cells kCoarseFactor
    /// times as wide instead (a few ground triangles far wider than the
    /// cells would otherwise make most of the pairs: truck_town's 94 % in
    /// 10 m cells). One: every triangle in the cells (the tests of the
    /// bucketing's exact contract).
    enum class Levels : std::uint8_t { one, two };
    static constexpr double kLargeCells = 16.0;
    static constexpr double kCoarseFactor = 4.0;
    UniformGrid(const std::vector<Triangle>& triangles, const Aabb& bounds, double car_radius_m, double cell_size_m,
                Levels levels);

    /// The cells a box covers (clamped to the grid; NaN counts as the lowest
    /// cell). Returns false if the box misses the grid's bounds (rounded
    /// outward to floats, like every triangle's box) entirely.
    bool cell_range(const Aabb& box, CellRange& out) const {
        if (slots_.empty() || !box.overlaps(reach_)) return false;
        for (int i = 0; i < 3; ++i) {
            out.lo[i] = coord(box.min[i], i);
            out.hi[i] = coord(box.max[i], i);
        }
        return true;
    }

    /// Calls f(triangle_index) once for every triangle whose bucket overlaps
    /// `box`'s cell range, in ascending cell order (x fastest, then y, then
    /// z), ascending triangle index within a cell; then the same over the
    /// coarse level's large triangles, if any.
    ///
    /// A box covering more cells than are occupied (a huge reach, e.g. from
    /// an absurd velocity) walks the occupied cells instead, in the same
    /// (key) order: the cost is bounded by the grid's size, never by the box.
    ///
    /// f may return bool: false stops the walk (any_candidate()).
    template <class F>
    void for_each_candidate(const Aabb& box, F&& f) const {
        if (!for_each_fine<true>(box, f) || coarse_.empty()) return;
        auto large = [&](std::uint32_t i) { return report(f, coarse_ids_[i]); };
        coarse_[0].for_each_fine<true>(box, large);
    }

    /// Calls f(triangle_index) for every triangle bucketed in a cell of
    /// `box`'s cell range, in the same order as for_each_candidate, but
    /// once per such cell (a triangle in two of them is reported twice):
    /// the walk without the owner-cell test, for a caller that sorts what
    /// it keeps and drops repeats itself (collect_overlapping's walk,
    /// before its box tests).
    template <class F>
    void for_each_bucketed(const Aabb& box, F&& f) const {
        for_each_fine<false>(box, f);
        if (coarse_.empty()) return;
        auto large = [&](std::uint32_t i) { f(coarse_ids_[i]); };
        coarse_[0].for_each_fine<false>(box, large);
    }

    /// Stores at out[n], out[n + 1], ... each triangle bucketed in a cell of
    /// `box`'s cell range whose box (box()) overlaps `box`, once per such
    /// cell, in for_each_bucketed's order, and returns the new count.
    /// `out` (the caller's scratch) grows as needed. The walk of
    /// for_each_bucketed with the test of each box, but a chunk of pairs
    /// (ChunkBoxes) whose box is outside `box` is dropped whole, and the
    /// boxes of one inside `box` along an axis are not tested along it.
    std::size_t collect_overlapping(const Aabb& box, std::vector<std::uint32_t>& out, std::size_t n) const {
        n = collect_level(box, out, n, [](std::uint32_t t) { return t; });
        if (coarse_.empty()) return n;
        return coarse_[0].collect_level(box, out, n, [&](std::uint32_t i) { return coarse_ids_[i]; });
    }

    /// True if pred(triangle_index) holds for a candidate of `box` (the walk
    /// of for_each_candidate, stopped at the first).
    template <class P>
    bool any_candidate(const Aabb& box, P&& pred) const {
        bool found = false;
        for_each_candidate(box, [&](std::uint32_t t) { return !(found = pred(t)); });
        return found;
    }

    /// The box triangle `t` is bucketed by: its bounds rounded outward to
    /// floats (it contains Triangle::bounds()).
    const FloatBox& box(std::uint32_t t) const { return boxes_[t]; }

    double cell_size_m() const { return cell_; }
    /// Triangles kept in the coarse level (see kLargeCells).
    std::size_t large_count() const { return coarse_ids_.size(); }
    /// Occupied cells (cells holding at least one triangle); empty cells
    /// take no memory.
    std::int64_t cell_count() const { return static_cast<std::int64_t>(empty_); }
    /// Triangle-cell pairs (both levels).
    std::size_t entry_count() const { return items_.size() + (coarse_.empty() ? 0 : coarse_[0].entry_count()); }
    /// Bytes held by the grid's arrays.
    std::size_t memory_bytes() const;
    /// Cells per axis of the (virtual) dense grid over the bounds.
    const std::int32_t* dims() const { return dims_; }

private:
    /// Builds the coarse level over the triangles marked in `large`.
    void build_coarse(const std::vector<Triangle>& triangles, const std::vector<char>& large, double car_radius_m);

    // This level's walk (for_each_candidate without the coarse level).
    // False if f asked to stop.
    template <bool kOnce, class F>
    bool for_each_fine(const Aabb& box, F& f) const {
        return for_each_cell(box, [&](std::uint32_t c, const CellRange& q, std::int32_t x, std::int32_t y,
                                      std::int32_t z) { return visit_cell<kOnce>(c, q, x, y, z, f); });
    }
    // collect_overlapping over this level (`id`: its triangle index to the
    // track's).
    template <class Id>
    std::size_t collect_level(const Aabb& box, std::vector<std::uint32_t>& out, std::size_t n, const Id& id) const;
    // Cell c's part of collect_level.
    template <class Id>
    std::size_t collect_cell(std::uint32_t c, const Aabb& box, const ChunkBoxes::Query& cq,
                             std::vector<std::uint32_t>& out, std::size_t n, const Id& id) const;
    // Stores items_[from, to) whose boxes overlap `box` along the axes in
    // kAxes (bit i: axis i; along the others they are known to) at at[n],
    // at[n + 1], ...; the new n.
    template <unsigned kAxes, class Id>
    std::size_t collect_along(std::uint32_t from, std::uint32_t to, const Aabb& box, std::uint32_t* at,
                              std::size_t n, const Id& id) const;
    // Calls visit(cell index, range, x, y, z) for each occupied cell of
    // `box`'s range (the empty cell for those not occupied), x fastest, then
    // y, then z; or, if the range holds more cells than are occupied, for
    // the occupied ones in it by key (the same order). False if visit
    // returned false (and stopped the walk).
    template <class V>
    bool for_each_cell(const Aabb& box, const V& visit) const;

    // 12 bytes: the key as two halves (no 8-byte alignment), and the
    // start of its triangles, which end where the next cell's start.
    struct Cell {
        std::uint32_t key_lo;  // dense index; kNoKey for the empty cell and the end marker
        std::uint32_t key_hi;
        std::uint32_t begin;  // its triangles: items_[begin, next cell's begin)
        std::uint64_t key() const { return (std::uint64_t{key_hi} << 32) | key_lo; }
    };
    static constexpr std::uint64_t kNoKey = ~std::uint64_t{0};  // above any dense index (< 2^63)

    static std::uint64_t u64(std::int32_t v) { return static_cast<std::uint64_t>(v); }
    // Fixed 64-bit mix (xor-shift, multiply: the murmur3 finaliser's first
    // round); the product's top bits depend on every key bit.
    std::size_t slot_of(std::uint64_t key) const {
        key ^= key >> 33;
        key *= 0xff51afd7ed558ccdull;
        return static_cast<std::size_t>(key >> shift_);
    }
    // The occupied-cell index of `key`, or empty_ (the empty cell).
    std::uint32_t find(std::uint64_t key) const {
        for (std::size_t i = slot_of(key);; i = (i + 1) & mask_) {
            const std::uint32_t c = slots_[i];
            if (cells_[c].key() == key || c == empty_) return c;
        }
    }
    // Reports the triangles of cell (x, y, z) whose owner cell, for query
    // range q, is this one. False if f asked to stop.
    template <bool kOnce, class F>
    bool visit_cell(std::uint32_t c, const CellRange& q, std::int32_t x, std::int32_t y, std::int32_t z,
                    F& f) const {
        const std::uint32_t end = cells_[c + 1].begin;
        for (std::uint32_t k = cells_[c].begin; k < end; ++k) {
            const std::uint32_t tri = items_[k];
            if constexpr (kOnce) {
                // Owner cell: lowest cell of the two ranges' overlap.
                const FloatBox& b = boxes_[tri];
                if (std::max(coord(b.lo[0], 0), q.lo[0]) != x || std::max(coord(b.lo[1], 1), q.lo[1]) != y ||
                    std::max(coord(b.lo[2], 2), q.lo[2]) != z) {
                    continue;
                }
            }
            if (!report(f, tri)) return false;
        }
        return true;
    }
    // Calls f(tri); false if f returns bool and asked to stop.
    template <class F>
    static bool report(F& f, std::uint32_t tri) {
        if constexpr (std::is_same_v<std::invoke_result_t<F&, std::uint32_t>, bool>) {
            return f(tri);
        } else {
            f(tri);
            return true;
        }
    }
    // floor((v - origin) / cell) clamped to the grid: for c >= 0 floor(c) >= k
    // exactly when c >= k (k an integer), and truncation is floor, so no
    // call to floor (a library call without SSE4.1) is needed.
    std::int32_t coord(double v, int axis) const {
        const double c = (v - origin_[axis]) * inv_cell_;
        if (!(c >= 0.0)) return 0;  // also catches NaN
        if (c >= static_cast<double>(dims_[axis] - 1)) return dims_[axis] - 1;
        return static_cast<std::int32_t>(c);
    }
    void set_cell_size(double cell_m);
    void build_table();

    Vec3 origin_{0, 0, 0};
    double cell_ = 1.0;
    double inv_cell_ = 1.0;
    std::int32_t dims_[3] = {1, 1, 1};
    Aabb bounds_;
    Aabb reach_;  // bounds_ rounded outward to floats: holds every triangle's box
    int shift_ = 63;                      // 64 - log2(slots_.size())
    std::size_t mask_ = 0;                // slots_.size() - 1
    std::uint32_t empty_ = 0;             // = cell_count(): what an empty slot holds
    std::vector<std::uint32_t> slots_;    // hash table: index into cells_, or empty_
    std::vector<Cell> cells_;             // occupied cells by ascending key, the empty cell, an end marker
    std::vector<std::uint32_t> items_;    // triangle indices, ascending per cell
    std::vector<FloatBox> boxes_;         // each triangle's box, rounded outward to floats
    ChunkBoxes chunks_;                   // the box around each chunk of items_
    std::vector<UniformGrid> coarse_;     // none or one: the level of the large triangles
    std::vector<std::uint32_t> coarse_ids_;  // coarse-level index -> triangle index
};

}  // namespace jetrace

// The definitions of the walks over a box's cells (for_each_cell and
// collect_overlapping's parts).
#include "jetrace/core/uniform_grid_walks.inl"
