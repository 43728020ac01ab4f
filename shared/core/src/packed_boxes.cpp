#include "jetrace/core/packed_boxes.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>

namespace jetrace {

void PackedBoxes::reset(std::size_t n) {
    n_ = n;
    stride_ = (n + kLanes - 1) / kLanes * kLanes;
    data_.resize(6 * stride_);
    if (stride_ == n) return;
    // The last block of each array made empty whole (set() then fills the
    // boxes that fall in it): one copy each, not a loop over the padding.
    constexpr float inf = std::numeric_limits<float>::infinity();
    static constexpr std::array<float, kLanes> kLower{inf, inf, inf, inf, inf, inf, inf, inf};
    static constexpr std::array<float, kLanes> kUpper{-inf, -inf, -inf, -inf, -inf, -inf, -inf, -inf};
    const std::size_t last = stride_ - kLanes;
    for (int i = 0; i < 3; ++i) {
        std::memcpy(lo(i) + last, kLower.data(), sizeof kLower);
        std::memcpy(hi(i) + last, kUpper.data(), sizeof kUpper);
    }
}

}  // namespace jetrace
