#include "jetrace/candidates.hpp"

#include <cassert>

namespace jetrace {

std::size_t Candidates::touching_from(std::size_t k, const Vec3& p, double reach_m) const {
    assert(!all && found.size() >= boxes.size());
    const double h = reach_m + kBoxSlack_m;
    const double h2 = h * h;
    const double px = p.x(), py = p.y(), pz = p.z();
    const std::size_t n = boxes.size();
    std::uint32_t* out = found.data();
    std::size_t count = 0;
    while (k < n) {
        const std::size_t group = k >> kGroupShift;
        const std::size_t group_end = std::min(n, (group + 1) << kGroupShift);
        if (box_distance2(groups[group], px, py, pz) <= h2) {
            while (k < group_end) {
                const std::size_t run = k >> kRunShift;
                const std::size_t end = std::min(n, (run + 1) << kRunShift);
                if (box_distance2(runs[run], px, py, pz) <= h2) {
                    for (; k < end; ++k) {
                        out[count] = static_cast<std::uint32_t>(k);
                        count += box_distance2(boxes[k], px, py, pz) <= h2 ? 1 : 0;
                    }
                }
                k = end;
            }
        }
        k = group_end;
    }
    return count;
}

}  // namespace jetrace
