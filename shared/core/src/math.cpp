#include "jetrace/core/math.hpp"

#include <bit>
#include <cmath>
#include <cstring>

namespace jetrace {

namespace {

// Reduces x into [-pi, pi] with plain arithmetic (deterministic).
double reduce_pi(double x) {
    const double two_pi = 2.0 * kPi;
    if (x > kPi || x < -kPi) {
        const double k = std::nearbyint(x / two_pi);
        x = x - k * two_pi;
    }
    return x;
}

// Taylor series of sin on [-pi/2, pi/2], Horner form in x^2, fixed order.
double sin_poly(double x) {
    const double x2 = x * x;
    double s = 1.0 / 6227020800.0;          // 1/13!
    s = s * x2 - 1.0 / 39916800.0;          // 1/11!
    s = s * x2 + 1.0 / 362880.0;            // 1/9!
    s = s * x2 - 1.0 / 5040.0;              // 1/7!
    s = s * x2 + 1.0 / 120.0;               // 1/5!
    s = s * x2 - 1.0 / 6.0;                 // 1/3!
    s = s * x2 + 1.0;
    return s * x;
}

}  // namespace

double det_sin(double x) {
    x = reduce_pi(x);
    // Fold into [-pi/2, pi/2]: sin(pi - x) = sin(x).
    if (x > kPi / 2) x = kPi - x;
    if (x < -kPi / 2) x = -kPi - x;
    return sin_poly(x);
}

double det_cos(double x) { return det_sin(x + kPi / 2); }

Quat axis_angle(const Vec3& axis, double angle_rad) {
    const double h = 0.5 * angle_rad;
    const double s = det_sin(h);
    return Quat(det_cos(h), axis.x() * s, axis.y() * s, axis.z() * s);
}

Quat shortest_arc(const Vec3& from, const Vec3& to) {
    const double c = from.dot(to);
    if (c < -1.0 + 1e-12) {
        // Half turn about any axis orthogonal to `from`: pick the world axis
        // least aligned with it, deterministically.
        Vec3 other = std::abs(from.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 0, 1);
        const Vec3 axis = from.cross(other).normalized();
        return Quat(0.0, axis.x(), axis.y(), axis.z());
    }
    const Vec3 axis = from.cross(to);
    const double s = std::sqrt((1.0 + c) * 2.0);
    const double inv = 1.0 / s;
    return Quat(0.5 * s, axis.x() * inv, axis.y() * inv, axis.z() * inv);
}

Quat nlerp_from_identity(const Quat& q, double t) {
    // Take the short way round.
    const double sign = q.w() < 0.0 ? -1.0 : 1.0;
    const double u = 1.0 - t;
    const double ts = t * sign;
    const double w = u + ts * q.w(), x = ts * q.x(), y = ts * q.y(), z = ts * q.z();
    // One square root and one division; Eigen's normalize() divides each
    // component separately.
    const double inv = 1.0 / std::sqrt(w * w + x * x + y * y + z * z);
    return Quat(w * inv, x * inv, y * inv, z * inv);
}

void Fnv1a::bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) {
        h_ ^= p[i];
        h_ *= 0x100000001b3ull;
    }
}

void Fnv1a::u32(std::uint32_t v) {
    unsigned char b[4];
    for (int i = 0; i < 4; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
    bytes(b, 4);
}

void Fnv1a::u64(std::uint64_t v) {
    unsigned char b[8];
    for (int i = 0; i < 8; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
    bytes(b, 8);
}

void Fnv1a::f64(double v) {
    // -0.0 and 0.0 hash differently on purpose: the hash is over raw bits.
    u64(std::bit_cast<std::uint64_t>(v));
}

}  // namespace jetrace
