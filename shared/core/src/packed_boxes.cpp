#include "jetrace/core/packed_boxes.hpp"

#include <algorithm>
#include <limits>

namespace jetrace {

void PackedBoxes::reset(std::size_t n) {
    n_ = n;
    const std::size_t padded = (n + kLanes - 1) / kLanes * kLanes;
    constexpr float inf = std::numeric_limits<float>::infinity();
    for (int i = 0; i < 3; ++i) {
        lo_[i].resize(padded);
        hi_[i].resize(padded);
        std::fill(lo_[i].begin() + static_cast<std::ptrdiff_t>(n), lo_[i].end(), inf);
        std::fill(hi_[i].begin() + static_cast<std::ptrdiff_t>(n), hi_[i].end(), -inf);
    }
}

}  // namespace jetrace
