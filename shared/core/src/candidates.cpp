#include "jetrace/core/candidates.hpp"

#include <bit>
#include <cassert>

namespace jetrace {

namespace {

// Stores the places of run `r` (its first place `first`) whose bits are set
// in `box_mask` at out[count], out[count + 1], ...; the new count. Every
// place is stored, the end moved past those within reach (which of a run's
// are is not predictable: no branch on it).
inline std::size_t store_run(std::uint32_t first, std::uint32_t box_mask, std::uint32_t* out, std::size_t count) {
    for (std::uint32_t i = 0; i < Candidates::kRunLength; ++i) {
        out[count] = first + i;
        count += (box_mask >> i) & 1u;
    }
    return count;
}

}  // namespace

std::size_t Candidates::touching_from(std::size_t k, const Vec3& p, double reach_m) const {
    assert(!all && found.size() >= boxes.size());
    const std::size_t n = boxes.size();
    if (k >= n) return 0;
    const BoxQuery q = boxes.query(p, reach_m);
    std::uint32_t* out = found.data();
    // One run (a car over a coarse mesh): its boxes at once, without the
    // run's and group's boxes, which could only skip this same test.
    if (n <= kRunLength) return store_run(0, boxes.within8(0, q) & (~std::uint32_t{0} << k), out, 0);
    std::size_t count = 0;
    const std::size_t first_run = k >> kRunShift;
    const std::size_t first_group = k >> kGroupShift;
    const bool one_group = groups.size() == 1;
    for (std::size_t g = first_group; g < groups.size(); ++g) {
        if (!one_group && !groups.within(g, q)) continue;
        // The group's runs at once (those before the k-th candidate's masked).
        std::uint32_t run_mask = runs.within8(g << kRunShift, q);
        if (g == first_group) run_mask &= ~std::uint32_t{0} << (first_run - (g << kRunShift));
        while (run_mask != 0) {
            const std::size_t r = (g << kRunShift) + static_cast<std::size_t>(std::countr_zero(run_mask));
            run_mask &= run_mask - 1;
            std::uint32_t box_mask = boxes.within8(r << kRunShift, q);
            if (r == first_run) box_mask &= ~std::uint32_t{0} << (k - (r << kRunShift));
            count = store_run(static_cast<std::uint32_t>(r << kRunShift), box_mask, out, count);
        }
    }
    return count;
}

}  // namespace jetrace
