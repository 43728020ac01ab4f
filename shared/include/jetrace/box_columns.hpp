// Boxes stored by column, tested against a point two at a time.
#pragma once

#include "jetrace/geometry.hpp"
#include "jetrace/math.hpp"

#include <cstddef>
#include <limits>
#include <vector>

namespace jetrace {

/// A list of boxes kept by pairs, each coordinate of a pair side by side
/// (min x, y, z, max x, y, z), padded to an even count with a box no point
/// is near, so that the distance test runs
/// on two boxes at once (the compiler's vector extension: SSE2 on x86-64,
/// NEON on aarch64, scalar code elsewhere). The test is within() of
/// Candidates, operation for operation: the same results, NaN included.
class BoxColumns {
public:
    void clear() {
        blocks_.clear();
        size_ = 0;
    }
    void push(const Aabb& b) {
        if (size_ % 2 == 0) blocks_.push_back(kFarBlock);
        Block& block = blocks_.back();
        const int lane = static_cast<int>(size_ % 2);
        for (int i = 0; i < 3; ++i) {
            block.col[i][lane] = b.min[i];
            block.col[3 + i][lane] = b.max[i];
        }
        ++size_;
    }
    std::size_t size() const { return size_; }

    /// The first box from the k-th on within sqrt(h2) of p (the distance
    /// from p to the box), or size() if none.
    std::size_t first_within(std::size_t k, const Vec3& p, double h2) const {
        for (std::size_t pair = k & ~std::size_t{1}; pair < size_; pair += 2) {
            const Lanes in = within(pair, p, h2);
            if (in[0] != 0 && pair >= k) return pair;
            if (in[1] != 0 && pair + 1 >= k) return pair + 1;  // never the padding: it is never near
        }
        return size_;
    }
    /// Calls f(k) for every box within sqrt(h2) of p, in ascending order.
    template <class F>
    void for_each_within(const Vec3& p, double h2, F&& f) const {
        for (std::size_t pair = 0; pair < size_; pair += 2) {
            const Lanes in = within(pair, p, h2);
            if (in[0] != 0) f(pair);
            if (in[1] != 0) f(pair + 1);
        }
    }

private:
    using Pair = double __attribute__((vector_size(16)));
    using Lanes = long long __attribute__((vector_size(16)));
    // Padding: a box at +infinity on every axis is at an infinite distance.
    static constexpr double kFar = std::numeric_limits<double>::infinity();

    // Two boxes: their min x, y, z and max x, y, z, each a pair.
    struct Block {
        Pair col[6];
    };
    static constexpr Block kFarBlock = {{{kFar, kFar}, {kFar, kFar}, {kFar, kFar}, {kFar, kFar}, {kFar, kFar}, {kFar, kFar}}};

    Pair load(int col, std::size_t k) const { return blocks_[k / 2].col[col]; }
    // std::max(a, b) lane by lane: a unless a < b (a NaN a stays).
    static Pair max(Pair a, Pair b) { return a < b ? b : a; }
    // Boxes k and k + 1 against p: the squared distance from p to each box
    // (per axis the larger of min - p, p - max and 0; summed x, y, z) at
    // most h2.
    Lanes within(std::size_t k, const Vec3& p, double h2) const {
        const Pair zero = {0.0, 0.0};
        Pair d2 = zero;
        for (int i = 0; i < 3; ++i) {
            const Pair pi = {p[i], p[i]};
            const Pair d = max(max(load(i, k) - pi, pi - load(3 + i, k)), zero);
            d2 = i == 0 ? d * d : d2 + d * d;
        }
        const Pair h = {h2, h2};
        return d2 <= h;
    }

    std::vector<Block> blocks_;
    std::size_t size_ = 0;
};

}  // namespace jetrace
