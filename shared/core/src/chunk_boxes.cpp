#include "jetrace/core/chunk_boxes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jetrace {

namespace {

// Every bound goes through this one function, the query's too: monotonic
// (a rounded difference, then a rounded product by a positive constant),
// so bounds keep their order in steps.
double to_steps(double v, double origin, double steps_per_m) { return (v - origin) * steps_per_m; }

bool finite(const FloatBox& b) {
    return std::isfinite(b.lo[0]) && std::isfinite(b.lo[1]) && std::isfinite(b.lo[2]) && std::isfinite(b.hi[0]) &&
           std::isfinite(b.hi[1]) && std::isfinite(b.hi[2]);
}

}  // namespace

void ChunkBoxes::build(const std::vector<std::uint32_t>& items, const std::vector<FloatBox>& boxes) {
    chunks_.assign((items.size() + kLength - 1) >> kShift, Bounds{0, 0, 0, 65535, 65535, 65535});
    if (items.empty()) return;
    const bool all_finite = std::all_of(items.begin(), items.end(), [&](std::uint32_t t) { return finite(boxes[t]); });
    if (!all_finite) {  // every query in steps NaN: no verdicts, every pair tested
        for (double& s : steps_per_m_) s = std::numeric_limits<double>::quiet_NaN();
        return;
    }
    FloatBox all = boxes[items[0]];
    for (std::uint32_t t : items) all.expand(boxes[t]);
    for (int i = 0; i < 3; ++i) {
        origin_[i] = all.lo[i];
        const double extent = static_cast<double>(all.hi[i]) - origin_[i];
        // A level flat along an axis: any positive scale keeps the order.
        steps_per_m_[i] = extent > 0.0 ? kUnits / extent : kUnits;
    }
    for (std::size_t c = 0; c < chunks_.size(); ++c) {
        const std::size_t first = c << kShift, end = std::min(first + kLength, items.size());
        FloatBox box = boxes[items[first]];
        for (std::size_t k = first + 1; k < end; ++k) box.expand(boxes[items[k]]);
        Bounds& b = chunks_[c];
        for (int i = 0; i < 3; ++i) {
            // Every bound is within rounding of [0, kUnits] steps: the clamp
            // at 65535 never applies, and the one at 0 raises a lower bound
            // at most to its boxes' own (none is below 0 steps).
            const double lo = std::floor(to_steps(box.lo[i], origin_[i], steps_per_m_[i])) - 1.0;
            const double hi = std::ceil(to_steps(box.hi[i], origin_[i], steps_per_m_[i])) + 1.0;
            b[static_cast<std::size_t>(i)] = static_cast<std::uint16_t>(std::clamp(lo, 0.0, 65535.0));
            b[static_cast<std::size_t>(i + 3)] = static_cast<std::uint16_t>(std::clamp(hi, 0.0, 65535.0));
        }
    }
}

ChunkBoxes::Query ChunkBoxes::query(const Aabb& box) const {
    Query q;
    for (int i = 0; i < 3; ++i) {
        const double lo = to_steps(box.min[i], origin_[i], steps_per_m_[i]);
        const double hi = to_steps(box.max[i], origin_[i], steps_per_m_[i]);
        q.below_lo[i] = lo - 0.5;
        q.above_lo[i] = lo + 0.5;
        q.below_hi[i] = hi - 0.5;
        q.above_hi[i] = hi + 0.5;
    }
    return q;
}

}  // namespace jetrace
