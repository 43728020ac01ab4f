#include "jetrace/core/packed_boxes.hpp"

#include <algorithm>
#include <limits>

namespace jetrace {

void PackedBoxes::reset(std::size_t n) {
    n_ = n;
    stride_ = (n + kLanes - 1) / kLanes * kLanes;
    data_.resize(6 * stride_);
    constexpr float inf = std::numeric_limits<float>::infinity();
    for (int i = 0; i < 3; ++i) {
        for (std::size_t k = n; k < stride_; ++k) {
            lo(i)[k] = inf;
            hi(i)[k] = -inf;
        }
    }
}

}  // namespace jetrace
