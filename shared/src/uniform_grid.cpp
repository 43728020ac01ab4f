#include "jetrace/uniform_grid.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace {

double UniformGrid::cell_size_for(const Aabb& bounds, double car_radius_m) {
    const Vec3 ext = (bounds.max - bounds.min).cwiseMax(Vec3(1, 1, 1));
    const double volume = ext.x() * ext.y() * ext.z();
    double size = 4.0 * car_radius_m;
    // Grow until the cell count fits (integer dims, so check the real count).
    size = std::max(size, std::cbrt(volume / static_cast<double>(kMaxCells)));
    for (;;) {
        std::int64_t n = 1;
        for (int i = 0; i < 3; ++i) n *= static_cast<std::int64_t>(std::floor(ext[i] / size)) + 1;
        if (n <= kMaxCells) return size;
        size *= 1.0625;
    }
}

std::int32_t UniformGrid::coord(double v, int axis) const {
    const double c = std::floor((v - origin_[axis]) * inv_cell_);
    if (!(c >= 0.0)) return 0;  // also catches NaN
    if (c >= static_cast<double>(dims_[axis] - 1)) return dims_[axis] - 1;
    return static_cast<std::int32_t>(c);
}

bool UniformGrid::cell_range(const Aabb& box, CellRange& out) const {
    if (cell_start_.empty() || !box.overlaps(bounds_)) return false;
    for (int i = 0; i < 3; ++i) {
        out.lo[i] = coord(box.min[i], i);
        out.hi[i] = coord(box.max[i], i);
    }
    return true;
}

UniformGrid::UniformGrid(const std::vector<Triangle>& triangles, const Aabb& bounds, double car_radius_m,
                         double cell_size_m) {
    bounds_ = bounds;
    origin_ = bounds.min;
    cell_ = cell_size_m > 0.0 ? cell_size_m : cell_size_for(bounds, car_radius_m);
    inv_cell_ = 1.0 / cell_;
    const Vec3 ext = bounds.max - bounds.min;
    for (int i = 0; i < 3; ++i) dims_[i] = static_cast<std::int32_t>(std::floor(ext[i] * inv_cell_)) + 1;

    tri_cells_.resize(triangles.size());
    const std::int64_t cells = cell_count();
    std::vector<std::uint32_t> counts(static_cast<std::size_t>(cells) + 1, 0);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        CellRange r;
        const Aabb b = triangles[t].bounds();
        for (int i = 0; i < 3; ++i) {
            r.lo[i] = coord(b.min[i], i);
            r.hi[i] = coord(b.max[i], i);
        }
        tri_cells_[t] = r;
        for (std::int32_t z = r.lo[2]; z <= r.hi[2]; ++z)
            for (std::int32_t y = r.lo[1]; y <= r.hi[1]; ++y)
                for (std::int32_t x = r.lo[0]; x <= r.hi[0]; ++x) ++counts[static_cast<std::size_t>(index(x, y, z))];
    }
    cell_start_.assign(static_cast<std::size_t>(cells) + 1, 0);
    std::uint32_t run = 0;
    for (std::int64_t c = 0; c < cells; ++c) {
        cell_start_[static_cast<std::size_t>(c)] = run;
        run += counts[static_cast<std::size_t>(c)];
    }
    cell_start_[static_cast<std::size_t>(cells)] = run;
    items_.resize(run);
    std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const CellRange& r = tri_cells_[t];
        for (std::int32_t z = r.lo[2]; z <= r.hi[2]; ++z)
            for (std::int32_t y = r.lo[1]; y <= r.hi[1]; ++y)
                for (std::int32_t x = r.lo[0]; x <= r.hi[0]; ++x)
                    items_[fill[static_cast<std::size_t>(index(x, y, z))]++] = static_cast<std::uint32_t>(t);
    }
}

std::size_t UniformGrid::memory_bytes() const {
    return cell_start_.size() * sizeof(std::uint32_t) + items_.size() * sizeof(std::uint32_t) +
           tri_cells_.size() * sizeof(CellRange);
}

}  // namespace jetrace
