#include "jetrace/chunk_boxes.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace {

namespace {

// Every bound goes through this one function, the query's too. It is
// monotonic (a rounded difference, then a rounded product by a positive
// constant), so bounds keep their order in steps: that is what makes the
// answers of classify() certain.
double to_steps(double v, double origin, double steps_per_m) { return (v - origin) * steps_per_m; }

}  // namespace

void ChunkBoxes::build(const std::vector<std::uint32_t>& items, const std::vector<FloatBox>& boxes) {
    chunks_.assign((items.size() + kLength - 1) >> kShift, Bounds{});
    if (items.empty()) return;
    FloatBox all = boxes[items[0]];
    for (std::uint32_t t : items) all.expand(boxes[t]);
    for (int i = 0; i < 3; ++i) {
        origin_[i] = all.lo[i];
        const double extent = static_cast<double>(all.hi[i]) - origin_[i];
        // A level flat along an axis: any positive scale keeps the order.
        steps_per_m_[i] = extent > 0.0 ? kUnits / extent : 1.0;
    }
    for (std::size_t c = 0; c < chunks_.size(); ++c) {
        const std::size_t first = c << kShift, end = std::min(first + kLength, items.size());
        FloatBox box = boxes[items[first]];
        for (std::size_t k = first + 1; k < end; ++k) box.expand(boxes[items[k]]);
        Bounds& b = chunks_[c];
        for (int i = 0; i < 3; ++i) {
            // One step outward beyond the floor and the ceiling: the box
            // holds its own bounds in steps with room (every bound lies
            // between 0 and kUnits steps, within rounding).
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
        q.lo[i] = to_steps(box.min[i], origin_[i], steps_per_m_[i]);
        q.hi[i] = to_steps(box.max[i], origin_[i], steps_per_m_[i]);
    }
    return q;
}

}  // namespace jetrace
