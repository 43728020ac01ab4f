// Deterministic math for the physics core.
//
// Vectors and quaternions are Eigen types. The core is compiled with
// EIGEN_DONT_VECTORIZE and -ffp-contract=off (see shared/core/CMakeLists.txt), so
// every reduction (dot, norm) is the same unrolled scalar sequence under gcc
// and clang at any optimisation level. Only +, -, *, / and sqrt are used on
// the step path: they are correctly rounded by IEEE 754. Trigonometry comes
// from the polynomials below, never from libm.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace jetrace {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

/// World axes: Y is up. A car's local frame: +Z forward, +Y up.
inline const Vec3 kWorldUp{0.0, 1.0, 0.0};
inline const Vec3 kLocalForward{0.0, 0.0, 1.0};
inline const Vec3 kLocalUp{0.0, 1.0, 0.0};

inline constexpr double kPi = 3.14159265358979323846;

/// Deterministic sine for |x| <= pi (range-reduced otherwise). Taylor series
/// evaluated in a fixed order; absolute error below 1e-15 on [-pi/4, pi/4]
/// and below 1e-9 on [-pi, pi]. Not for hot loops: the step only calls it
/// with small angles.
double det_sin(double x);
/// Deterministic cosine, same contract as det_sin.
double det_cos(double x);

/// Quaternion for a rotation of `angle_rad` about unit `axis`.
Quat axis_angle(const Vec3& axis, double angle_rad);

/// The shortest rotation taking unit vector `from` onto unit vector `to`.
/// For opposite vectors it rotates half a turn about an axis orthogonal to
/// `from` chosen deterministically.
Quat shortest_arc(const Vec3& from, const Vec3& to);

/// Normalised linear interpolation from identity towards `q` by t in [0, 1]
/// (the deterministic stand-in for slerp; for the small per-step angles used
/// here the two differ by far less than the quantisation step).
Quat nlerp_from_identity(const Quat& q, double t);

/// `v / |v|`, or `fallback` when |v| is below `min_len`.
[[gnu::always_inline]] inline Vec3 normalized_or(const Vec3& v, const Vec3& fallback, double min_len = 1e-12) {
    const double n2 = v.squaredNorm();
    if (!(n2 > min_len * min_len)) return fallback;
    return v * (1.0 / std::sqrt(n2));
}

namespace quantize_detail {
// Round to nearest, ties to even, without a libm call: adding and
// subtracting kMagic (1.5 * 2^52) leaves no fraction bits, exactly for
// magnitudes below kFastLimit (2^51); without fast-math the compiler may
// not fold the pair away.
inline constexpr double kMagic = 6755399441055744.0;
inline constexpr double kFastLimit = 2251799813685248.0;
}  // namespace quantize_detail

/// Rounds x to the nearest multiple of 2^-bits (ties to even). Exact and
/// deterministic: scaling by a power of two never rounds.
inline double quantize(double x, int bits) {
    using quantize_detail::kMagic;
    const double scale = static_cast<double>(std::uint64_t{1} << bits);  // exact power of two
    // Multiplying by 2^-bits gives the same correctly rounded value as
    // dividing by 2^bits (both round the same exact quotient), only cheaper.
    const double inv_scale = 1.0 / scale;
    const double y = x * scale;
    if (std::fabs(y) < quantize_detail::kFastLimit) return ((y + kMagic) - kMagic) * inv_scale;
    return std::nearbyint(y) * inv_scale;
}

/// Each coordinate of v rounded to a multiple of 2^-bits.
inline void quantize(Vec3& v, int bits) {
    for (int i = 0; i < 3; ++i) v[i] = quantize(v[i], bits);
}

namespace quantize_detail {
// Two lanes of doubles, and of their bits (GCC and Clang vector extensions:
// SSE2 on x86-64, NEON on aarch64, scalar code where a target has no vectors).
using D2 = double __attribute__((vector_size(16)));
using I2 = std::int64_t __attribute__((vector_size(16)));
// All lanes -1 where |y| is below kFastLimit (quantize()'s fast path), else 0 (NaN included).
inline I2 in_range(D2 y) {
    const I2 magnitude{0x7fffffffffffffff, 0x7fffffffffffffff};
    const D2 limit{kFastLimit, kFastLimit};
    return reinterpret_cast<D2>(reinterpret_cast<I2>(y) & magnitude) < limit;
}
// quantize()'s rounding of y (scaled, in range), times `inv`.
inline D2 rounded(D2 y, D2 inv) {
    const D2 magic{kMagic, kMagic};
    return ((y + magic) - magic) * inv;
}
}  // namespace quantize_detail

/// quantize(a, bits_a) and quantize(b, bits_b) together, two coordinates
/// at a time in 2-lane vectors. Lane by lane these are quantize()'s
/// operations (a multiplication by a power of two, the add and subtract of
/// 1.5 * 2^52, a multiplication), each correctly rounded by IEEE 754 in a
/// vector lane as in a scalar register, so the bits are quantize()'s; a
/// coordinate outside the magic number's range (or NaN) sends all six
/// through quantize() itself.
inline void quantize(Vec3& a, int bits_a, Vec3& b, int bits_b) {
    using quantize_detail::D2;
    using quantize_detail::I2;
    const double sa = static_cast<double>(std::uint64_t{1} << bits_a);
    const double sb = static_cast<double>(std::uint64_t{1} << bits_b);
    const D2 y0 = D2{a.x(), a.y()} * D2{sa, sa};
    const D2 y1 = D2{a.z(), b.x()} * D2{sa, sb};
    const D2 y2 = D2{b.y(), b.z()} * D2{sb, sb};
    const I2 fits = quantize_detail::in_range(y0) & quantize_detail::in_range(y1) & quantize_detail::in_range(y2);
    if (!(fits[0] != 0 && fits[1] != 0)) {
        quantize(a, bits_a);
        quantize(b, bits_b);
        return;
    }
    const double ia = 1.0 / sa, ib = 1.0 / sb;
    const D2 r0 = quantize_detail::rounded(y0, D2{ia, ia});
    const D2 r1 = quantize_detail::rounded(y1, D2{ia, ib});
    const D2 r2 = quantize_detail::rounded(y2, D2{ib, ib});
    a = Vec3(r0[0], r0[1], r1[0]);
    b = Vec3(r1[1], r2[0], r2[1]);
}

/// Each of q's four coefficients rounded to a multiple of 2^-bits, two at a
/// time as above (the same bits as quantize() on each).
inline void quantize(Quat& q, int bits) {
    using quantize_detail::D2;
    using quantize_detail::I2;
    const double scale = static_cast<double>(std::uint64_t{1} << bits);
    const D2 s{scale, scale};
    const D2 y0 = D2{q.x(), q.y()} * s;
    const D2 y1 = D2{q.z(), q.w()} * s;
    const I2 fits = quantize_detail::in_range(y0) & quantize_detail::in_range(y1);
    if (!(fits[0] != 0 && fits[1] != 0)) {
        q = Quat(quantize(q.w(), bits), quantize(q.x(), bits), quantize(q.y(), bits), quantize(q.z(), bits));
        return;
    }
    const double inv = 1.0 / scale;
    const D2 r0 = quantize_detail::rounded(y0, D2{inv, inv});
    const D2 r1 = quantize_detail::rounded(y1, D2{inv, inv});
    q = Quat(r1[1], r0[0], r0[1], r1[0]);  // (w, x, y, z)
}

/// q / |q| for a quaternion already within about 1e-3 of unit length (such
/// as a quantised unit quaternion, |q|^2 - 1 below 2e-4): one Newton step for
/// 1/sqrt, no sqrt or division, leaves |q| - 1 below 2e-8 (a thousandth of
/// the quantisation step); falls back to an exact normalisation farther
/// from unit.
[[gnu::always_inline]] inline Quat normalized_near_unit(const Quat& q) {
    const double w = q.w(), x = q.x(), y = q.y(), z = q.z();
    const double n2 = w * w + x * x + y * y + z * z;
    if (!(n2 > 0.999 && n2 < 1.001)) {
        if (!(n2 > 0.0)) return q;  // zero (or NaN): nothing to normalise
        const double inv = 1.0 / std::sqrt(n2);
        return Quat(w * inv, x * inv, y * inv, z * inv);
    }
    const double k = 1.5 - 0.5 * n2;
    return Quat(w * k, x * k, y * k, z * k);
}

/// Bit-for-bit equality of every component (+0 and -0 compare equal), in
/// plain scalar code: cheaper than Eigen's `==` on the step path.
inline bool same(const Vec3& a, const Vec3& b) { return a.x() == b.x() && a.y() == b.y() && a.z() == b.z(); }

/// Identical bits in every component (-0 differs from +0): the test for
/// reusing what a pure function worked out from these very values.
inline bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), 3 * sizeof(double)) == 0; }
inline bool same_bits(const Quat& a, const Quat& b) {
    return std::memcmp(a.coeffs().data(), b.coeffs().data(), 4 * sizeof(double)) == 0;
}

/// Image of local +Y (up) under unit quaternion q.
inline Vec3 axis_y(const Quat& q) {
    const double w = q.w(), x = q.x(), y = q.y(), z = q.z();
    return {2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x)};
}
/// Image of local +Z (forward) under unit quaternion q.
inline Vec3 axis_z(const Quat& q) {
    const double w = q.w(), x = q.x(), y = q.y(), z = q.z();
    return {2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y)};
}

/// 64-bit FNV-1a over raw bytes; used for state hashes and track identity.
class Fnv1a {
public:
    void bytes(const void* data, std::size_t n);
    void u8(std::uint8_t v) { bytes(&v, 1); }
    void u32(std::uint32_t v);
    void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
    void u64(std::uint64_t v);
    void f64(double v);
    void vec3(const Vec3& v) { f64(v.x()); f64(v.y()); f64(v.z()); }
    std::uint64_t value() const { return h_; }

private:
    std::uint64_t h_ = 0xcbf29ce484222325ull;
};

}  // namespace jetrace
