#include "jetrace/core/candidates.hpp"

#include <array>
#include <bit>
#include <cassert>
#include <cstring>

namespace jetrace {

namespace {

// For each 8-bit mask: the places of its set bits, lowest first (the rest
// zero), and how many there are.
struct RunPlaces {
    std::array<std::array<std::uint32_t, Candidates::kRunLength>, 256> places{};
    std::array<std::uint8_t, 256> count{};
    constexpr RunPlaces() {
        for (std::uint32_t mask = 0; mask < 256; ++mask) {
            std::uint8_t c = 0;
            for (std::uint32_t i = 0; i < Candidates::kRunLength; ++i) {
                if ((mask >> i) & 1u) places[mask][c++] = i;
            }
            count[mask] = c;
        }
    }
};
constexpr RunPlaces kRunPlaces;

using Found8 = std::uint32_t __attribute__((vector_size(32)));

// Stores the places of run `r` (its first place `first`) whose bits are set
// in `box_mask` at out[count], out[count + 1], ...; the new count. A whole
// run of eight is written (out has room for it), the end moved past those
// within reach: no branch on which of a run's boxes are.
inline std::size_t store_run(std::uint32_t first, std::uint32_t box_mask, std::uint32_t* out, std::size_t count) {
    static_assert(Candidates::kRunLength == 8);
    assert(box_mask < 256);
    Found8 found;
    std::memcpy(&found, kRunPlaces.places[box_mask].data(), sizeof found);
    found += first;
    std::memcpy(out + count, &found, sizeof found);
    return count + kRunPlaces.count[box_mask];
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
