// A car's candidate boxes packed for testing eight at a time.
//
// The boxes are the grid's: each triangle's bounds rounded outward to
// floats (UniformGrid::box), one array per bound and axis (structure of
// arrays), so a test reads 8 boxes' lower x bounds in one load, and so on,
// and tests them together in 4-lane float vectors (GCC and Clang vector
// extensions: SSE2 on x86-64, NEON on aarch64, scalar code where a target
// has no vectors). A gather only copies them.
//
// A test is conservative: it accepts every box whose exact distance to the
// point is within the reach (plus kBoxSlack_m), the rounding of the point
// to floats and of the float arithmetic included (BoxQuery widens the
// reach to cover both: by about 2^-23 of the point's coordinates, 0.1 mm
// a kilometre from the world's origin). It may accept a box that much
// beyond; callers decide with exact tests on the triangles, so a box test
// changes what they cost, never what they find.
#pragma once

#include "jetrace/core/geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace jetrace {

/// Slack added to every bounding-box test of a candidate (unit: m), so that
/// rounding can never make a box test reject a triangle the exact distance
/// test would accept. Far below the position quantum (1/1024 m).
inline constexpr double kBoxSlack_m = 1e-6;

/// A point and reach to test packed boxes against (PackedBoxes::query).
struct BoxQuery {
    float p[3] = {0, 0, 0};  ///< the point, rounded to floats
    float reach = 0;         ///< the reach, widened to cover rounding (unit: m)
    float reach2 = 0;        ///< its square, widened again
    bool none = true;        ///< no box can be within reach (NaN, or absurdly far)
};

namespace packed_detail {
using F4 = float __attribute__((vector_size(16)));
using I4 = std::int32_t __attribute__((vector_size(16)));

inline F4 load4(const float* at) {
    F4 v;
    std::memcpy(&v, at, sizeof v);
    return v;
}
inline F4 splat4(float f) { return F4{f, f, f, f}; }
#if defined(__SSE2__)
// a > b ? a : b per lane, b where either is NaN: what MAXPS computes, one
// instruction (the generic code below in three).
inline F4 max4(F4 a, F4 b) { return reinterpret_cast<F4>(_mm_max_ps(reinterpret_cast<__m128>(a), reinterpret_cast<__m128>(b))); }
// Bit i set where lane i of a comparison's mask is set (MOVMSKPS).
inline std::uint32_t lane_bits(I4 in) {
    return static_cast<std::uint32_t>(_mm_movemask_ps(_mm_castsi128_ps(reinterpret_cast<__m128i>(in))));
}
#else
inline F4 max4(F4 a, F4 b) {
    const I4 mask = a > b;
    return reinterpret_cast<F4>((reinterpret_cast<I4>(a) & mask) | (reinterpret_cast<I4>(b) & ~mask));
}
inline std::uint32_t lane_bits(I4 in) {
    const I4 bits = in & I4{1, 2, 4, 8};
    return static_cast<std::uint32_t>(bits[0] | bits[1] | bits[2] | bits[3]);
}
#endif
}  // namespace packed_detail

class PackedBoxes {
public:
    /// Boxes per test. Storage is padded to a multiple of it with empty boxes
    /// (lower bounds +infinity, upper -infinity), which no test accepts.
    static constexpr std::size_t kLanes = 8;

    /// Holds `n` boxes, each to be set (the padding after them is empty).
    void reset(std::size_t n);
    /// Box k.
    void set(std::size_t k, const FloatBox& b) {
        for (int i = 0; i < 3; ++i) {
            lo(i)[k] = b.lo[i];
            hi(i)[k] = b.hi[i];
        }
    }
    /// Box k.
    FloatBox box(std::size_t k) const {
        FloatBox b;
        for (int i = 0; i < 3; ++i) {
            b.lo[i] = lo(i)[k];
            b.hi[i] = hi(i)[k];
        }
        return b;
    }
    std::size_t size() const { return n_; }

    /// The query for point `p` and reach `reach_m` (unit: m).
    BoxQuery query(const Vec3& p, double reach_m) const;

    /// Bit i set if box first + i (first: a multiple of kLanes, below the
    /// padded size) is within the query's reach of its point.
    std::uint32_t within8(std::size_t first, const BoxQuery& q) const {
        using namespace packed_detail;
        if (q.none) return 0;
        std::uint32_t mask = 0;
        for (std::size_t half = 0; half < kLanes; half += 4) {
            const std::size_t at = first + half;
            F4 d2 = splat4(0.0f);
            for (int i = 0; i < 3; ++i) {
                const F4 p = splat4(q.p[i]);
                const F4 above = p - load4(hi(i) + at);
                const F4 below = load4(lo(i) + at) - p;
                F4 gap = max4(above, below);        // NaN: below
                gap = max4(splat4(0.0f), gap);      // NaN stays NaN
                d2 = d2 + gap * gap;
            }
            const I4 in = d2 <= splat4(q.reach2);
            mask |= packed_detail::lane_bits(in) << half;
        }
        return mask;
    }
    /// Box k alone, by exactly the arithmetic of within8.
    bool within(std::size_t k, const BoxQuery& q) const {
        if (q.none) return false;
        float d2 = 0.0f;
        for (int i = 0; i < 3; ++i) {
            const float above = q.p[i] - hi(i)[k];
            const float below = lo(i)[k] - q.p[i];
            float gap = above > below ? above : below;
            gap = 0.0f > gap ? 0.0f : gap;
            d2 = d2 + gap * gap;
        }
        return d2 <= q.reach2;
    }
    /// Bit i set if box first + i (first: a multiple of kLanes, below the
    /// padded size) is within the reach along every axis: within_along_axes
    /// for eight boxes, by the same arithmetic.
    std::uint32_t within8_along_axes(std::size_t first, const BoxQuery& q) const {
        using namespace packed_detail;
        if (q.none) return 0;
        std::uint32_t mask = 0;
        for (std::size_t half = 0; half < kLanes; half += 4) {
            const std::size_t at = first + half;
            I4 in = I4{-1, -1, -1, -1};
            for (int i = 0; i < 3; ++i) {
                in &= splat4(q.p[i] + q.reach) >= load4(lo(i) + at);
                in &= splat4(q.p[i] - q.reach) <= load4(hi(i) + at);
            }
            mask |= lane_bits(in) << half;
        }
        return mask;
    }
    /// Box k within the reach along every axis (its distance along each
    /// axis, not the Euclidean one): the sweep's test.
    bool within_along_axes(std::size_t k, const BoxQuery& q) const {
        if (q.none) return false;
        bool in = true;
        for (int i = 0; i < 3; ++i) in = in && q.p[i] + q.reach >= lo(i)[k] && q.p[i] - q.reach <= hi(i)[k];
        return in;
    }

private:
    std::size_t n_ = 0;
    // Axis i's lower bounds of every box, then its upper bounds (each
    // array padded to a multiple of kLanes: `stride_` floats), in one
    // vector: lower x, y, z, upper x, y, z.
    const float* lo(int i) const { return data_.data() + static_cast<std::size_t>(i) * stride_; }
    const float* hi(int i) const { return data_.data() + static_cast<std::size_t>(i + 3) * stride_; }
    float* lo(int i) { return data_.data() + static_cast<std::size_t>(i) * stride_; }
    float* hi(int i) { return data_.data() + static_cast<std::size_t>(i + 3) * stride_; }

    std::size_t stride_ = 0;
    std::vector<float> data_;
};

inline BoxQuery PackedBoxes::query(const Vec3& p, double reach_m) const {
    BoxQuery q;
    const double far = std::max({std::abs(p.x()), std::abs(p.y()), std::abs(p.z())});
    // NaN fails both. Beyond these bounds floats could overflow; no box
    // of a track (within kMaxTrackCoordinate_m) is within reach of such a
    // point, and no reach a car uses is that long.
    if (!(far <= 1e30) || !(reach_m >= 0.0 && reach_m <= 1e18)) return q;
    // The point rounds to floats by at most far * 2^-24; each float
    // difference, sum and square rounds by 2^-24 of what it holds, and
    // so do the reach and its square rounded to floats. Widening the
    // reach by twice the first and both by 2^-18 covers them with room
    // to spare.
    const double h = reach_m + kBoxSlack_m + far * 0x1p-23 + 1e-9;
    for (int i = 0; i < 3; ++i) q.p[i] = static_cast<float>(p[i]);
    q.reach = static_cast<float>(h * (1.0 + 0x1p-18));
    q.reach2 = static_cast<float>(h * h * (1.0 + 0x1p-18));
    q.none = false;
    return q;
}

}  // namespace jetrace
