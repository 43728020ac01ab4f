#include "jetrace/core/uniform_grid.hpp"

#include <algorithm>
#include <bit>
#include <memory>
#include <utility>

namespace jetrace {
namespace {

// Extent of `b` along `axis` (unit: m); 0 if negative or not finite.
double extent(const Aabb& b, int axis) {
    const double e = b.max[axis] - b.min[axis];
    return std::isfinite(e) && e > 0.0 ? e : 0.0;
}

// Cells along an axis of extent `ext` with edge `size`, computed as
// set_cell_size does (via the reciprocal).
double axis_cells(double ext, double size) { return std::floor(ext * (1.0 / size)) + 1.0; }

// `size` times the smallest power of 1.0625 that keeps every axis of `b`
// within kMaxAxisCells. A size that is not positive (no valid radius) starts
// from the finest edge the key allows.
double fit_axes(const Aabb& b, double size) {
    if (!(size > 0.0)) {
        double widest = 0.0;
        for (int i = 0; i < 3; ++i) widest = std::max(widest, extent(b, i));
        size = widest > 0.0 ? widest / UniformGrid::kMaxAxisCells : 1.0;
    }
    for (;;) {
        bool fits = true;
        for (int i = 0; i < 3; ++i) fits = fits && axis_cells(extent(b, i), size) <= UniformGrid::kMaxAxisCells;
        if (fits) return size;
        size *= 1.0625;
    }
}

// Cells in a range (0 if empty, as for a NaN box).
double range_cells(const CellRange& r) {
    double n = 1.0;
    for (int i = 0; i < 3; ++i) n *= std::max(0, r.hi[i] - r.lo[i] + 1);
    return n;
}

// The occupied cells in ascending key order, with their CSR offsets and
// items (ascending triangle index within a cell).
struct SortedCells {
    std::vector<std::uint64_t> keys;
    std::vector<std::uint32_t> start;  // keys.size() + 1
    std::vector<std::uint32_t> items;
};

// Every (cell key, triangle) pair of the buckets `ranges` (`total` pairs in
// all), sorted by key then triangle: a counting sort by the key's top bits
// into about total / 4 buckets (in triangle order), then each bucket sorted.
// A pair is one 64-bit word: the key's bits below the bucket's, then the
// triangle's.
SortedCells sort_cells(const std::vector<CellRange>& ranges, const std::int32_t dims[3], std::size_t total) {
    const std::size_t n = ranges.size();
    const auto dx = static_cast<std::uint64_t>(dims[0]);
    const auto dy = static_cast<std::uint64_t>(dims[1]);
    const std::uint64_t last_key = dx * dy * static_cast<std::uint64_t>(dims[2]) - 1;
    const int key_bits = static_cast<int>(std::bit_width(last_key));
    const int tri_bits = static_cast<int>(std::bit_width(n > 0 ? n - 1 : std::size_t{0}));
    const int bucket_bits =
        std::max(std::clamp(static_cast<int>(std::bit_width(total)) - 2, 1, 22), key_bits + tri_bits - 64);
    const int low_bits = std::max(0, key_bits - bucket_bits);  // <= 64 - tri_bits
    const std::uint64_t low_mask = (std::uint64_t{1} << low_bits) - 1;
    const std::uint64_t tri_mask = (std::uint64_t{1} << tri_bits) - 1;
    const auto for_each_pair = [&](auto&& emit) {
        for (std::size_t t = 0; t < n; ++t) {
            const CellRange& r = ranges[t];
            for (std::int32_t z = r.lo[2]; z <= r.hi[2]; ++z) {
                for (std::int32_t y = r.lo[1]; y <= r.hi[1]; ++y) {
                    const std::uint64_t row = (static_cast<std::uint64_t>(z) * dy + static_cast<std::uint64_t>(y)) * dx;
                    for (std::int32_t x = r.lo[0]; x <= r.hi[0]; ++x) emit(row + static_cast<std::uint64_t>(x), t);
                }
            }
        }
    };
    // next[b + 1] counts bucket b; after the prefix sum next[b] is where
    // bucket b starts, and after the fill where it ends.
    std::vector<std::uint32_t> next(static_cast<std::size_t>(last_key >> low_bits) + 2, 0);
    for_each_pair([&](std::uint64_t key, std::size_t) { ++next[(key >> low_bits) + 1]; });
    for (std::size_t b = 1; b < next.size(); ++b) next[b] += next[b - 1];
    // Not zero-filled: the fill writes every word.
    const auto list = std::make_unique_for_overwrite<std::uint64_t[]>(total);
    for_each_pair([&](std::uint64_t key, std::size_t t) {
        list[next[key >> low_bits]++] = ((key & low_mask) << tri_bits) | t;
    });
    std::size_t occupied = 0;
    for (std::size_t b = 0, begin = 0; b + 1 < next.size(); begin = next[b++]) {
        std::sort(list.get() + begin, list.get() + next[b]);
        for (std::size_t k = begin; k < next[b]; ++k)
            occupied += (k == begin || (list[k] >> tri_bits) != (list[k - 1] >> tri_bits)) ? 1 : 0;
    }
    SortedCells out;
    out.keys.reserve(occupied);
    out.start.reserve(occupied + 1);
    out.items.resize(total);
    for (std::size_t b = 0, begin = 0; b + 1 < next.size(); begin = next[b++]) {
        for (std::size_t k = begin; k < next[b]; ++k) {
            if (k == begin || (list[k] >> tri_bits) != (list[k - 1] >> tri_bits)) {
                out.keys.push_back((static_cast<std::uint64_t>(b) << low_bits) | (list[k] >> tri_bits));
                out.start.push_back(static_cast<std::uint32_t>(k));
            }
            out.items[k] = static_cast<std::uint32_t>(list[k] & tri_mask);
        }
    }
    out.start.push_back(static_cast<std::uint32_t>(total));
    return out;
}

}  // namespace

std::int64_t UniformGrid::entry_budget(std::size_t triangles) {
    // Item offsets are 32-bit, and the empty cell's index must fit too.
    constexpr std::int64_t kOffsetLimit = (std::int64_t{1} << 32) - 2;
    const auto capped = static_cast<std::int64_t>(std::min<std::size_t>(triangles, std::size_t{1} << 30));
    const std::int64_t per_tri = kEntriesPerTriangle * capped;
    return std::min(kOffsetLimit, std::max(kMinEntryBudget, per_tri));
}

double UniformGrid::typical_extent_m(const std::vector<Triangle>& triangles) {
    if (triangles.empty()) return 0.0;
    std::vector<double> largest(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const Aabb b = triangles[t].bounds();
        largest[t] = std::max({extent(b, 0), extent(b, 1), extent(b, 2)});
    }
    const auto mid = largest.begin() + static_cast<std::ptrdiff_t>(largest.size() / 2);
    std::nth_element(largest.begin(), mid, largest.end());
    return *mid;
}

double UniformGrid::cell_size_for(const std::vector<Triangle>& triangles, const Aabb& bounds, double car_radius_m) {
    const double lo = kMinCellRadii * car_radius_m, hi = kMaxCellRadii * car_radius_m;
    const double typical = typical_extent_m(triangles);
    // Not std::clamp: lo is NaN for a NaN radius (fit_axes then starts
    // from the finest edge the key allows).
    return fit_axes(bounds, typical > lo ? std::min(typical, hi) : lo);
}

void UniformGrid::set_cell_size(double cell_m) {
    cell_ = cell_m;
    inv_cell_ = 1.0 / cell_m;
    for (int i = 0; i < 3; ++i) dims_[i] = static_cast<std::int32_t>(std::floor(extent(bounds_, i) * inv_cell_)) + 1;
}

UniformGrid::UniformGrid(const std::vector<Triangle>& triangles, const Aabb& bounds, double car_radius_m,
                         double cell_size_m, Levels levels) {
    const bool with_coarse = levels == Levels::two;
    bounds_ = bounds;
    reach_ = FloatBox::around(bounds).aabb();
    origin_ = bounds.min;
    const std::size_t n = triangles.size();

    // Bucket every triangle; grow the edge while the pairs exceed the budget
    // (by the square root of the excess: a large flat triangle's pairs fall
    // with the square of the edge).
    double size = cell_size_m > 0.0 ? fit_axes(bounds, cell_size_m) : cell_size_for(triangles, bounds, car_radius_m);
    const double budget = static_cast<double>(entry_budget(n));
    std::vector<CellRange> ranges(n);
    // Large triangles (more than kLargeCells cells) go to the coarse level:
    // a few ground triangles far wider than the cells would otherwise make
    // most of the pairs (truck_town: 94 % of them in 10 m cells).
    std::vector<char> large(n, 0);
    std::size_t large_count = 0;
    double pairs = 0.0;
    boxes_.resize(n);
    for (std::size_t t = 0; t < n; ++t) boxes_[t] = FloatBox::around(triangles[t].bounds());
    for (;;) {
        set_cell_size(size);
        pairs = 0.0;
        large_count = 0;
        for (std::size_t t = 0; t < n; ++t) {
            const FloatBox& b = boxes_[t];
            CellRange& r = ranges[t];
            for (int i = 0; i < 3; ++i) {
                r.lo[i] = coord(b.lo[i], i);
                r.hi[i] = coord(b.hi[i], i);
            }
            const double cells = range_cells(r);
            large[t] = with_coarse && cells > kLargeCells ? 1 : 0;
            if (large[t] != 0) {
                ++large_count;
            } else {
                pairs += cells;
            }
        }
        if (pairs <= budget) break;
        size = fit_axes(bounds, size * std::max(1.0625, std::sqrt(pairs / budget)));
    }
    if (large_count > 0) {
        build_coarse(triangles, large, car_radius_m);
        // No pairs in this level: an empty range.
        for (std::size_t t = 0; t < n; ++t) {
            if (large[t] != 0) ranges[t] = CellRange{{0, 0, 0}, {-1, -1, -1}};
        }
    }

    SortedCells sorted = sort_cells(ranges, dims_, static_cast<std::size_t>(pairs));
    std::vector<CellRange>().swap(ranges);
    items_ = std::move(sorted.items);
    const std::size_t occupied = sorted.keys.size();
    cells_.resize(occupied + 2);
    const auto cell = [](std::uint64_t key, std::uint32_t begin) {
        return Cell{static_cast<std::uint32_t>(key), static_cast<std::uint32_t>(key >> 32), begin};
    };
    for (std::size_t c = 0; c < occupied; ++c) cells_[c] = cell(sorted.keys[c], sorted.start[c]);
    // The empty cell's triangles: [total, total).
    const auto total = static_cast<std::uint32_t>(items_.size());
    cells_[occupied] = cell(kNoKey, total);
    cells_[occupied + 1] = cell(kNoKey, total);
    build_table();
    chunks_.build(items_, boxes_);
}

void UniformGrid::build_coarse(const std::vector<Triangle>& triangles, const std::vector<char>& large,
                               double car_radius_m) {
    std::vector<Triangle> big;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        if (large[t] == 0) continue;
        big.push_back(triangles[t]);
        coarse_ids_.push_back(static_cast<std::uint32_t>(t));
    }
    // The same bounds (a query clamps to them alike); cells kCoarseFactor
    // times as wide, and no third level.
    coarse_.push_back(UniformGrid(big, bounds_, car_radius_m, cell_ * kCoarseFactor, Levels::one));
}

void UniformGrid::build_table() {
    const std::size_t occupied = cells_.size() - 2;  // less the empty cell and the end marker
    std::size_t capacity = 2;
    while (capacity < 2 * occupied) capacity *= 2;  // load <= 0.5
    empty_ = static_cast<std::uint32_t>(occupied);
    mask_ = capacity - 1;
    shift_ = 64 - std::countr_zero(capacity);
    slots_.assign(capacity, empty_);
    // In ascending key order, so the layout depends on the geometry only.
    for (std::size_t c = 0; c < occupied; ++c) {
        std::size_t i = slot_of(cells_[c].key());
        while (slots_[i] != empty_) i = (i + 1) & mask_;
        slots_[i] = static_cast<std::uint32_t>(c);
    }
}

std::size_t UniformGrid::memory_bytes() const {
    return slots_.size() * sizeof(std::uint32_t) + cells_.size() * sizeof(Cell) +
           items_.size() * sizeof(std::uint32_t) + boxes_.size() * sizeof(FloatBox) + chunks_.memory_bytes() +
           coarse_ids_.size() * sizeof(std::uint32_t) + (coarse_.empty() ? 0 : coarse_[0].memory_bytes());
}

}  // namespace jetrace
