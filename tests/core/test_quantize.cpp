// The state's rounding to the wire resolution, two coordinates at a time
// (quantize(Vec3&, int, Vec3&, int) and quantize(Quat&, int), 2-lane
// vectors): bit for bit what quantize() gives one coordinate at a time, on
// the values a race makes, on ties and signed zeros, and on what the
// vector path hands to the scalar one (magnitudes past 2^51 once scaled,
// infinities, NaN) in any lane.
//
// Random tests draw from std::mt19937_64 (JETRACE_TEST_SEED replays one;
// see tests/support/test_seed.hpp).
#include "jetrace/core/hovercar.hpp"
#include "jetrace/core/math.hpp"

#include "support/test_seed.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

using namespace jetrace;

namespace {

std::uint64_t bits_of(double x) {
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
}

// The pair rounded together must equal each coordinate rounded alone (NaN:
// the same bits, as quantize() keeps them).
void expect_pair_matches(const Vec3& a, int bits_a, const Vec3& b, int bits_b) {
    Vec3 pa = a, pb = b;
    quantize(pa, bits_a, pb, bits_b);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(bits_of(pa[i]), bits_of(quantize(a[i], bits_a))) << "a[" << i << "] = " << a[i];
        EXPECT_EQ(bits_of(pb[i]), bits_of(quantize(b[i], bits_b))) << "b[" << i << "] = " << b[i];
    }
}

void expect_quat_matches(const Quat& q, int bits) {
    Quat r = q;
    quantize(r, bits);
    EXPECT_EQ(bits_of(r.w()), bits_of(quantize(q.w(), bits))) << "w = " << q.w();
    EXPECT_EQ(bits_of(r.x()), bits_of(quantize(q.x(), bits))) << "x = " << q.x();
    EXPECT_EQ(bits_of(r.y()), bits_of(quantize(q.y(), bits))) << "y = " << q.y();
    EXPECT_EQ(bits_of(r.z()), bits_of(quantize(q.z(), bits))) << "z = " << q.z();
}

}  // namespace

TEST(Quantize, PairsMatchOneCoordinateAtATimeOnRaceValues) {
    JETRACE_SEEDED_RNG(rng);
    std::uniform_real_distribution<double> position(-5000.0, 5000.0), velocity(-400.0, 400.0), unit(-1.0, 1.0);
    for (int i = 0; i < 20000; ++i) {
        const Vec3 p(position(rng), position(rng), position(rng));
        const Vec3 v(velocity(rng), velocity(rng), velocity(rng));
        expect_pair_matches(p, kPosBits, v, kVelBits);
        // Other resolutions per side (the lanes that mix the two vectors).
        expect_pair_matches(p, 3, v, 20);
        expect_quat_matches(Quat(unit(rng), unit(rng), unit(rng), unit(rng)), kQuatBits);
        if (testing::Test::HasFailure()) return;
    }
}

TEST(Quantize, PairsMatchOnTiesSignedZerosAndTheEdgeOfTheFastPath) {
    const double q = std::ldexp(1.0, -kPosBits);
    const double limit = std::ldexp(1.0, 51 - kPosBits);  // 2^51 once scaled
    const std::vector<double> values{0.0,       -0.0,          0.5 * q,        -0.5 * q,     1.5 * q,
                                     -2.5 * q,  q * 0.4999999, limit,          -limit,       std::nextafter(limit, 0.0),
                                     limit * 4, -limit * 1e6,  1e300,          -1e-300,      1234.56789};
    for (double x : values) {
        for (double y : values) {
            expect_pair_matches(Vec3(x, y, 1.0), kPosBits, Vec3(y, 2.0, x), kVelBits);
            expect_quat_matches(Quat(x, y, 0.25, -0.75), kQuatBits);
        }
    }
}

TEST(Quantize, NonFiniteInAnyLaneTakesTheScalarPath) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    for (int lane = 0; lane < 6; ++lane) {
        for (double bad : {nan, inf, -inf}) {
            double c[6] = {1.25, -3.5, 700.001, 0.0009765625, -12.3, 45.6};
            c[lane] = bad;
            expect_pair_matches(Vec3(c[0], c[1], c[2]), kPosBits, Vec3(c[3], c[4], c[5]), kVelBits);
            if (lane < 4) {
                double w[4] = {0.5, -0.5, 0.5, 0.5};
                w[lane] = bad;
                expect_quat_matches(Quat(w[0], w[1], w[2], w[3]), kQuatBits);
            }
        }
    }
}

TEST(Quantize, QuantizeMotionIsThePairOfItsVectors) {
    CarState car;
    car.position = Vec3(10.12345678, -0.0001, 2047.99999);
    car.velocity = Vec3(-99.000488281, 0.00048828125, 1e-9);
    CarState alone = car;
    quantize_motion(car);
    quantize(alone.position, kPosBits);
    quantize(alone.velocity, kVelBits);
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(bits_of(car.position[i]), bits_of(alone.position[i]));
        EXPECT_EQ(bits_of(car.velocity[i]), bits_of(alone.velocity[i]));
    }
}
