// Closest point on a triangle, and the uniform grid against brute force.
//
// Random tests draw from std::mt19937_64. The seed is fixed by default; set
// the environment variable JETRACE_TEST_SEED (decimal or 0x-hex) to run with
// another one. Every random test prints the seed it used on failure
// (SCOPED_TRACE) and records it as the test property "seed" (visible with
// --gtest_output=xml), so a failure can be replayed with
//   JETRACE_TEST_SEED=<seed> ./test_geometry_grid --gtest_filter=<test>
#include "jetrace/builtin_tracks.hpp"
#include "jetrace/geometry.hpp"
#include "jetrace/resolver.hpp"
#include "jetrace/settings.hpp"
#include "jetrace/track.hpp"
#include "jetrace/uniform_grid.hpp"
#include "jetrace/world.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace jetrace;

namespace {

// ---------------------------------------------------------------- seeds

std::uint64_t base_seed() {
    if (const char* e = std::getenv("JETRACE_TEST_SEED"); e != nullptr && *e != '\0') {
        return std::strtoull(e, nullptr, 0);
    }
    return 0x6a65747261636501ull;
}

// Seeds the generator, prints the seed on failure and records it.
#define JETRACE_SEEDED_RNG(rng)                                                                    \
    const std::uint64_t rng##_seed = base_seed();                                                  \
    SCOPED_TRACE("JETRACE_TEST_SEED=" + std::to_string(rng##_seed));                               \
    ::testing::Test::RecordProperty("seed", std::to_string(rng##_seed));                           \
    std::mt19937_64 rng(rng##_seed)

double uniform(std::mt19937_64& rng, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}

Vec3 random_in_box(std::mt19937_64& rng, const Vec3& lo, const Vec3& hi) {
    return {uniform(rng, lo.x(), hi.x()), uniform(rng, lo.y(), hi.y()), uniform(rng, lo.z(), hi.z())};
}

Vec3 random_unit(std::mt19937_64& rng) {
    for (;;) {
        const Vec3 v(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
        const double n2 = v.squaredNorm();
        if (n2 > 1e-4 && n2 <= 1.0) return v / std::sqrt(n2);
    }
}

// A uniformly distributed point on triangle t.
Vec3 random_on_triangle(std::mt19937_64& rng, const Triangle& t) {
    double u = uniform(rng, 0, 1), v = uniform(rng, 0, 1);
    if (u + v > 1) {
        u = 1 - u;
        v = 1 - v;
    }
    return t.a + (t.b - t.a) * u + (t.c - t.a) * v;
}

std::string str(const Vec3& v) {
    std::ostringstream o;
    o.precision(17);
    o << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
    return o.str();
}

const char* name(TriRegion r) {
    switch (r) {
        case TriRegion::vertex_a: return "vertex_a";
        case TriRegion::vertex_b: return "vertex_b";
        case TriRegion::vertex_c: return "vertex_c";
        case TriRegion::edge_ab: return "edge_ab";
        case TriRegion::edge_bc: return "edge_bc";
        case TriRegion::edge_ca: return "edge_ca";
        case TriRegion::face: return "face";
    }
    return "?";
}

// ------------------------------------------------ independent distance oracle
//
// Written without reference to the implementation, in quadruple precision
// (__float128, or long double where that is already IEEE quad): differences
// and products of the double coordinates are (nearly) exact, so even the
// plane of a nearly degenerate sliver is well defined (long double was not
// enough there: its own error reached 1e-7 m on 1000 m x 1e-9 m slivers).
// distance = min(distance to each of the three edge segments, distance to the
// plane if the projection falls inside the triangle, decided by the signs of
// the three sub-triangle areas). This is the exact Euclidean distance for any
// triangle, degenerate or not (a zero-area triangle is the union of its edges).

#if defined(__SIZEOF_FLOAT128__)
__extension__ typedef __float128 W;
#else
typedef long double W;
#endif
struct LV {
    W x, y, z;
};
LV lv(const Vec3& v) { return {W(v.x()), W(v.y()), W(v.z())}; }
LV sub(LV a, LV b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
LV add(LV a, LV b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
LV mul(LV a, W s) { return {a.x * s, a.y * s, a.z * s}; }
W dot(LV a, LV b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
LV cross(LV a, LV b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double root(W x) { return static_cast<double>(std::sqrt(static_cast<long double>(x))); }

W oracle_segment_d2(LV p, LV a, LV b) {
    const LV ab = sub(b, a);
    const W len2 = dot(ab, ab);
    W t = 0;
    if (len2 > 0) t = std::clamp(W(dot(sub(p, a), ab) / len2), W(0), W(1));
    const LV d = sub(p, add(a, mul(ab, t)));
    return dot(d, d);
}

double oracle_distance(const Vec3& pd, const Triangle& tri) {
    const LV p = lv(pd), a = lv(tri.a), b = lv(tri.b), c = lv(tri.c);
    W best = std::min({oracle_segment_d2(p, a, b), oracle_segment_d2(p, b, c), oracle_segment_d2(p, c, a)});
    const LV n = cross(sub(b, a), sub(c, a));
    const W nn = dot(n, n);
    if (nn > 0) {
        const W s = dot(sub(p, a), n) / nn;
        const LV q = sub(p, mul(n, s));
        const bool inside = dot(cross(sub(b, a), sub(q, a)), n) >= 0 && dot(cross(sub(c, b), sub(q, b)), n) >= 0 &&
                            dot(cross(sub(a, c), sub(q, c)), n) >= 0;
        if (inside) {
            const LV d = sub(p, q);
            best = std::min(best, dot(d, d));
        }
    }
    return root(best);
}

double longest_edge(const Triangle& t) {
    return std::max({(t.b - t.a).norm(), (t.c - t.b).norm(), (t.a - t.c).norm()});
}

// Checks closest_point_on_triangle(p, t) against the oracle: the distance
// agrees to 1e-9 relative (relative to max(distance, 1 m), so that points on
// or next to the triangle are held to 1e-9 m), the returned point lies on the
// triangle, and the reported region is consistent with the point.
::testing::AssertionResult agrees_with_oracle(const Vec3& p, const Triangle& t) {
    const ClosestPoint cp = closest_point_on_triangle(p, t);
    const double d_impl = (p - cp.point).norm();
    const double d_ref = oracle_distance(p, t);
    // Slivers (Triangle::thin): the plane normal comes from a cross product
    // with a tiny edge, so double precision itself limits the distance to
    // about 1e-16 * length^2 / height (1e-4 m for 1000 m x 1 um; measured:
    // 7e-7 m). They are held to that conditioning bound, and never looser
    // than 1e-7 m, which is still 10^4 below the state quantum.
    double tol = 1e-9 * std::max(d_ref, 1.0);
    if (t.thin) {
        const double len = longest_edge(t);
        const double height = (t.b - t.a).cross(t.c - t.a).norm() / len;
        tol = std::max(1e-7 * std::max(d_ref, 1.0), 1e-16 * len * len / height);
    }
    auto fail = [&](const char* what) {
        return ::testing::AssertionFailure()
               << what << ": p=" << str(p) << " tri=" << str(t.a) << str(t.b) << str(t.c) << " degenerate=" << t.degenerate
               << " impl point=" << str(cp.point) << " region=" << name(cp.region) << " d_impl=" << d_impl
               << " d_oracle=" << d_ref << " diff=" << (d_impl - d_ref) << " tol=" << tol;
    };
    if (!(std::abs(d_impl - d_ref) <= tol)) return fail("distance differs from the oracle");
    // The returned point is on the triangle.
    const double scale = std::max(longest_edge(t), 1.0);
    if (!(oracle_distance(cp.point, t) <= 1e-9 * scale)) return fail("returned point is not on the triangle");
    // Region consistency.
    switch (cp.region) {
        case TriRegion::vertex_a:
            if (cp.point != t.a) return fail("vertex_a but point != a");
            break;
        case TriRegion::vertex_b:
            if (cp.point != t.b) return fail("vertex_b but point != b");
            break;
        case TriRegion::vertex_c:
            if (cp.point != t.c) return fail("vertex_c but point != c");
            break;
        case TriRegion::edge_ab:
            if (!(root(oracle_segment_d2(lv(cp.point), lv(t.a), lv(t.b))) <= 1e-9 * scale))
                return fail("edge_ab but point off edge ab");
            break;
        case TriRegion::edge_bc:
            if (!(root(oracle_segment_d2(lv(cp.point), lv(t.b), lv(t.c))) <= 1e-9 * scale))
                return fail("edge_bc but point off edge bc");
            break;
        case TriRegion::edge_ca:
            if (!(root(oracle_segment_d2(lv(cp.point), lv(t.c), lv(t.a))) <= 1e-9 * scale))
                return fail("edge_ca but point off edge ca");
            break;
        case TriRegion::face:
            if (t.degenerate) return fail("degenerate triangle reported a face region");
            break;
    }
    return ::testing::AssertionSuccess();
}

void expect_vec_near(const Vec3& got, const Vec3& want, double tol, const std::string& what) {
    EXPECT_LE((got - want).norm(), tol) << what << ": got " << str(got) << " want " << str(want);
}

}  // namespace

// ===================================================== closest point: regions

// Right triangle in the plane y = 0; every expected point is exact.
TEST(ClosestPoint, EveryRegionOfAKnownTriangle) {
    const Triangle t = Triangle::make(Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 0, 4));
    ASSERT_FALSE(t.degenerate);
    struct Case {
        Vec3 p;
        Vec3 point;
        TriRegion region;
    };
    const Case cases[] = {
        {Vec3(-1, 3, -1), Vec3(0, 0, 0), TriRegion::vertex_a},
        {Vec3(-2, -5, -0.5), Vec3(0, 0, 0), TriRegion::vertex_a},
        {Vec3(5, 2, -1), Vec3(4, 0, 0), TriRegion::vertex_b},
        {Vec3(7, -1, 0.5), Vec3(4, 0, 0), TriRegion::vertex_b},
        {Vec3(-1, -2, 5), Vec3(0, 0, 4), TriRegion::vertex_c},
        {Vec3(0.5, 9, 6), Vec3(0, 0, 4), TriRegion::vertex_c},
        {Vec3(2, 1, -3), Vec3(2, 0, 0), TriRegion::edge_ab},
        {Vec3(3, -4, -0.25), Vec3(3, 0, 0), TriRegion::edge_ab},
        {Vec3(3, 5, 3), Vec3(2, 0, 2), TriRegion::edge_bc},
        {Vec3(4, -1, 2), Vec3(3, 0, 1), TriRegion::edge_bc},
        {Vec3(-3, 1, 2), Vec3(0, 0, 2), TriRegion::edge_ca},
        {Vec3(-0.5, -7, 1), Vec3(0, 0, 1), TriRegion::edge_ca},
        {Vec3(1, 7, 1), Vec3(1, 0, 1), TriRegion::face},
        {Vec3(0.5, -3, 2.5), Vec3(0.5, 0, 2.5), TriRegion::face},
        {Vec3(1, 0, 1), Vec3(1, 0, 1), TriRegion::face},  // on the face itself
    };
    for (const Case& c : cases) {
        const ClosestPoint cp = closest_point_on_triangle(c.p, t);
        expect_vec_near(cp.point, c.point, 1e-12, "p=" + str(c.p));
        EXPECT_EQ(cp.region, c.region) << "p=" << str(c.p) << " got " << name(cp.region) << " want " << name(c.region);
        EXPECT_TRUE(agrees_with_oracle(c.p, t));
    }
}

// A general triangle in 3D: points are built inside each Voronoi region from
// the geometry, so the expected closest point is known.
TEST(ClosestPoint, EveryRegionOfATiltedTriangle) {
    const Vec3 a(1.5, 2.0, -3.0), b(9.0, 4.5, 1.0), c(-2.0, 7.0, 5.5);
    const Triangle t = Triangle::make(a, b, c);
    ASSERT_FALSE(t.degenerate);
    const Vec3 n = t.normal;
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    EXPECT_NEAR(n.dot(b - a), 0.0, 1e-12);
    EXPECT_NEAR(n.dot(c - a), 0.0, 1e-12);
    const Vec3 verts[3] = {a, b, c};
    const TriRegion vregion[3] = {TriRegion::vertex_a, TriRegion::vertex_b, TriRegion::vertex_c};
    const TriRegion eregion[3] = {TriRegion::edge_ab, TriRegion::edge_bc, TriRegion::edge_ca};
    for (double h : {-3.0, 0.0, 0.7, 4.0}) {
        for (int i = 0; i < 3; ++i) {
            const Vec3& v = verts[i];
            const Vec3& next = verts[(i + 1) % 3];
            const Vec3& prev = verts[(i + 2) % 3];
            // Vertex region: away from both adjacent edges.
            const Vec3 out = -((next - v).normalized() + (prev - v).normalized()).normalized();
            const Vec3 pv = v + out * 2.5 + n * h;
            ClosestPoint cp = closest_point_on_triangle(pv, t);
            EXPECT_EQ(cp.region, vregion[i]) << "h=" << h << " got " << name(cp.region);
            expect_vec_near(cp.point, v, 1e-12, "vertex region");
            EXPECT_TRUE(agrees_with_oracle(pv, t));
            // Edge region: outward from the edge's midpoint, in the plane.
            const Vec3 mid = (v + next) * 0.5;
            const Vec3 edge = (next - v).normalized();
            Vec3 outward = edge.cross(n);
            if (outward.dot(mid - prev) < 0) outward = -outward;
            const Vec3 pe = mid + outward * 1.75 + n * h;
            cp = closest_point_on_triangle(pe, t);
            EXPECT_EQ(cp.region, eregion[i]) << "h=" << h << " got " << name(cp.region);
            expect_vec_near(cp.point, mid, 1e-12, "edge region");
            EXPECT_TRUE(agrees_with_oracle(pe, t));
        }
        const Vec3 centroid = (a + b + c) / 3.0;
        const Vec3 pf = centroid + n * h;
        const ClosestPoint cp = closest_point_on_triangle(pf, t);
        EXPECT_EQ(cp.region, TriRegion::face) << "h=" << h << " got " << name(cp.region);
        expect_vec_near(cp.point, centroid, 1e-12, "face region");
        EXPECT_TRUE(agrees_with_oracle(pf, t));
    }
}

TEST(ClosestPoint, SegmentHelper) {
    const Vec3 a(1, 1, 1), b(5, 1, 1);
    expect_vec_near(closest_point_on_segment(Vec3(0, 3, 1), a, b), a, 0, "before a");
    expect_vec_near(closest_point_on_segment(Vec3(9, 3, 1), a, b), b, 0, "after b");
    expect_vec_near(closest_point_on_segment(Vec3(2, 3, -4), a, b), Vec3(2, 1, 1), 1e-15, "inside");
    expect_vec_near(closest_point_on_segment(Vec3(2, 3, -4), a, a), a, 0, "zero-length segment");
}

// =================================================== closest point: oracle

namespace {

// Random points around t: a box around the triangle expanded by its size, and
// points close to the triangle (within 1e-3 m or 3 m of a point on it).
struct Agreement {
    int samples = 0;
    int failures = 0;
    double worst_abs_m = 0;  // largest |d_impl - d_oracle|
    std::string first_failure;
};

Agreement sample_agreement(std::mt19937_64& rng, const Triangle& t, int n) {
    Agreement out;
    const Aabb box = t.bounds();
    const double size = std::max(longest_edge(t), 1e-3);
    const Vec3 pad(size, size, size);
    for (int i = 0; i < n; ++i) {
        Vec3 p;
        switch (i % 3) {
            case 0: p = random_in_box(rng, box.min - pad, box.max + pad); break;
            case 1: p = random_on_triangle(rng, t) + random_unit(rng) * uniform(rng, 0, 1e-3); break;
            default: p = random_on_triangle(rng, t) + random_unit(rng) * uniform(rng, 0, 3.0); break;
        }
        ++out.samples;
        out.worst_abs_m =
            std::max(out.worst_abs_m, std::abs((p - closest_point_on_triangle(p, t).point).norm() - oracle_distance(p, t)));
        const auto r = agrees_with_oracle(p, t);
        if (!r) {
            if (out.failures == 0) out.first_failure = r.message();
            ++out.failures;
        }
    }
    return out;
}

void random_points_agree(std::mt19937_64& rng, const Triangle& t, int n, const std::string& label,
                         const char* known_bug = nullptr) {
    const Agreement a = sample_agreement(rng, t, n);
    EXPECT_EQ(a.failures, 0) << (known_bug != nullptr ? known_bug : "") << label << ": " << a.failures << " of "
                             << a.samples << " random points disagree with the oracle; worst |d_impl - d_oracle| = "
                             << a.worst_abs_m << " m; first: " << a.first_failure;
}

// Rotates and translates a triangle rigidly (so its coordinates are not exact).
Triangle moved(std::mt19937_64& rng, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Eigen::Matrix3d rot = Quat(Eigen::AngleAxisd(uniform(rng, 0, 6.28), random_unit(rng))).toRotationMatrix();
    const Vec3 off = random_in_box(rng, Vec3(-300, -300, -300), Vec3(300, 300, 300));
    return Triangle::make(rot * a + off, rot * b + off, rot * c + off);
}

}  // namespace

TEST(ClosestPoint, OracleSanityAgainstDenseBarycentricSampling) {
    // The oracle itself against a dense barycentric sampling (an upper bound
    // on the distance, tight to the sampling pitch).
    JETRACE_SEEDED_RNG(rng);
    const Triangle t = Triangle::make(Vec3(0, 0, 0), Vec3(6, 1, 0), Vec3(2, 5, 3));
    const int k = 300;
    const double pitch = longest_edge(t) / k;
    for (int s = 0; s < 30; ++s) {
        const Vec3 p = random_in_box(rng, Vec3(-5, -5, -5), Vec3(10, 10, 10));
        double best = 1e300;
        for (int i = 0; i <= k; ++i) {
            for (int j = 0; i + j <= k; ++j) {
                const Vec3 q = t.a + (t.b - t.a) * (double(i) / k) + (t.c - t.a) * (double(j) / k);
                best = std::min(best, (p - q).norm());
            }
        }
        const double d = oracle_distance(p, t);
        EXPECT_LE(d, best + 1e-12) << str(p);
        EXPECT_GE(d, best - pitch) << str(p);
        EXPECT_TRUE(agrees_with_oracle(p, t));
    }
}

TEST(ClosestPoint, RandomPointsOrdinaryTriangles) {
    JETRACE_SEEDED_RNG(rng);
    for (int k = 0; k < 50; ++k) {
        const double size = std::exp(uniform(rng, std::log(0.1), std::log(60.0)));
        const Vec3 a = random_unit(rng) * size, b = random_unit(rng) * size, c = random_unit(rng) * size;
        const Triangle t = moved(rng, a, b, c);
        random_points_agree(rng, t, 400, "triangle " + std::to_string(k));
    }
}

TEST(ClosestPoint, DegenerateTriangles) {
    JETRACE_SEEDED_RNG(rng);
    struct Named {
        const char* label;
        Vec3 a, b, c;
    };
    const Named shapes[] = {
        {"collinear, c between a and b", Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(4, 0, 0)},
        {"collinear, c beyond b", Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(25, 0, 0)},
        {"collinear, c before a", Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(-7, 0, 0)},
        {"collinear, skew line", Vec3(1, 2, 3), Vec3(4, 8, 12), Vec3(2.5, 5, 7.5)},
        {"two equal vertices a=b", Vec3(3, 1, 2), Vec3(3, 1, 2), Vec3(-5, 4, 9)},
        {"two equal vertices b=c", Vec3(3, 1, 2), Vec3(-5, 4, 9), Vec3(-5, 4, 9)},
        {"two equal vertices c=a", Vec3(3, 1, 2), Vec3(-5, 4, 9), Vec3(3, 1, 2)},
        {"all the same point", Vec3(7, -2, 5), Vec3(7, -2, 5), Vec3(7, -2, 5)},
    };
    for (const Named& s : shapes) {
        const Triangle t0 = Triangle::make(s.a, s.b, s.c);
        EXPECT_TRUE(t0.degenerate) << s.label;
        EXPECT_EQ(t0.normal, Vec3::Zero()) << s.label;
        random_points_agree(rng, t0, 600, std::string(s.label) + " (axis coordinates)");
    }
    // Exactly collinear vertices survive translation but not rotation; the
    // rotated ones stay (nearly) zero area and must still be classified
    // degenerate or, if not, handled as a (tiny) triangle.
    for (const Named& s : shapes) {
        const Triangle t = moved(rng, s.a, s.b, s.c);
        random_points_agree(rng, t, 600, std::string(s.label) + " (moved)");
    }
    // The single-point triangle: closest point is that point from anywhere.
    const Triangle pt = Triangle::make(Vec3(7, -2, 5), Vec3(7, -2, 5), Vec3(7, -2, 5));
    for (int i = 0; i < 100; ++i) {
        const Vec3 p = random_in_box(rng, Vec3(-50, -50, -50), Vec3(50, 50, 50));
        EXPECT_EQ(closest_point_on_triangle(p, pt).point, Vec3(7, -2, 5));
    }
}

namespace {

struct Sliver {
    double length, height, apex;  // apex: where along the base the third vertex sits (fraction)
};

void slivers_agree(std::mt19937_64& rng, const std::vector<Sliver>& slivers, bool expect_non_degenerate,
                   const char* known_bug) {
    for (const Sliver& s : slivers) {
        const Vec3 a(0, 0, 0), b(s.length, 0, 0), c(s.apex * s.length, s.height, 0);
        std::ostringstream label;
        label << "sliver " << s.length << " m long, " << s.height << " m high, apex at " << s.apex;
        const Triangle axis = Triangle::make(a, b, c);
        if (expect_non_degenerate) {
            EXPECT_FALSE(axis.degenerate) << label.str() << " should go through the Voronoi-region code";
        }
        random_points_agree(rng, axis, 1500, label.str() + " (axis-aligned, degenerate=" +
                                                 std::to_string(axis.degenerate) + ")", known_bug);
        for (int k = 0; k < 3; ++k) {
            const Triangle t = moved(rng, a, b, c);
            random_points_agree(rng, t, 1500, label.str() + " (moved, degenerate=" + std::to_string(t.degenerate) + ")",
                                known_bug);
        }
    }
}

}  // namespace

// Long, thin triangles whose shape is still well conditioned (height/length
// 1e-2), and extremely thin ones (height/length <= 1e-11) that
// Triangle::make classifies as degenerate and handles as three segments.
TEST(ClosestPoint, SliverTrianglesWellConditionedOrDegenerate) {
    JETRACE_SEEDED_RNG(rng);
    slivers_agree(rng,
                  {{1000.0, 10.0, 0.5}, {1000.0, 10.0, 0.0}, {1000.0, 10.0, 1.0}, {500.0, 5.0, 0.37}, {60.0, 0.6, 0.9}},
                  true, nullptr);
    for (const Sliver& s : std::vector<Sliver>{{1000.0, 1e-9, 0.5}, {300.0, 1e-12, 0.6}, {60.0, 1e-10, 0.1}}) {
        EXPECT_TRUE(Triangle::make(Vec3(0, 0, 0), Vec3(s.length, 0, 0), Vec3(s.apex * s.length, s.height, 0)).degenerate)
            << s.length << " x " << s.height;
    }
    slivers_agree(rng, {{1000.0, 1e-9, 0.5}, {300.0, 1e-12, 0.6}, {60.0, 1e-10, 0.1}}, false, nullptr);
}

// Very long, very thin triangles between those two regimes (height/length
// from 1e-5 to 2e-10): non-degenerate for Triangle::make, so they must be
// handled exactly like any other triangle. (Before Triangle::thin, the
// Voronoi-region arithmetic cancelled here and was off by up to metres.)
TEST(ClosestPoint, SliverTrianglesThin) {
    // p lies ON the triangle (distance 0); the region arithmetic used to
    // return a point about 0.43 m away.
    const Triangle t = Triangle::make(Vec3(0, 0, 0), Vec3(1000, 0, 0), Vec3(500, 1e-4, 0));
    ASSERT_FALSE(t.degenerate);
    const Vec3 p(251, 5e-5, 0);
    const ClosestPoint cp = closest_point_on_triangle(p, t);
    EXPECT_LE((cp.point - p).norm(), 1e-9)
        << "p = (251, 5e-5, 0) is on the triangle (0,0,0) (1000,0,0) (500,1e-4,0), but "
        << "closest_point_on_triangle returns " << str(cp.point) << " (region " << name(cp.region) << "), "
        << (cp.point - p).norm() << " m away";

    JETRACE_SEEDED_RNG(rng);
    slivers_agree(rng,
                  {{1000.0, 1e-2, 0.5}, {1000.0, 1e-3, 0.25}, {1000.0, 1e-4, 0.5}, {60.0, 1e-4, 0.9},
                   {1000.0, 1e-6, 0.25}, {60.0, 1e-8, 0.5}},
                  true, nullptr);
}

// =========================================================== grid vs brute

namespace {

constexpr double kQueryRadius = 2.5 + 0.05;  // car radius + contact skin

// Brute force: indices (ascending) of every triangle within `radius` of c.
// A conservative box rejection (a centre outside a triangle's box expanded by
// radius + 1e-6 m is farther than radius from the triangle) keeps it fast;
// every triangle it does not reject goes through the same
// closest_point_on_triangle test the grid candidates go through.
struct BruteForce {
    const Track* track;
    double radius;
    // Each triangle's box expanded by radius + 1e-6 m, as flat arrays.
    std::vector<std::array<double, 6>> expanded;

    BruteForce(const Track& t, double radius_m) : track(&t), radius(radius_m) {
        const double m = radius_m + 1e-6;
        expanded.reserve(t.triangles.size());
        for (const Triangle& tri : t.triangles) {
            const Aabb b = tri.bounds();
            expanded.push_back({b.min.x() - m, b.min.y() - m, b.min.z() - m, b.max.x() + m, b.max.y() + m, b.max.z() + m});
        }
    }
    void within(const Vec3& c, std::vector<std::uint32_t>& out) const {
        out.clear();
        const double r2 = radius * radius;
        const double cx = c.x(), cy = c.y(), cz = c.z();
        for (std::size_t i = 0; i < expanded.size(); ++i) {
            const auto& e = expanded[i];
            // Outside the box expanded by the radius (plus a rounding margin):
            // farther than the radius from the box, hence from the triangle.
            if (cx < e[0] || cx > e[3] || cy < e[1] || cy > e[4] || cz < e[2] || cz > e[5]) continue;
            const Vec3 q = closest_point_on_triangle(c, track->triangles[i]).point;
            if ((c - q).squaredNorm() <= r2) out.push_back(static_cast<std::uint32_t>(i));
        }
    }
};

// Query centres: half uniform in the bounds expanded by 10 m, half within 5 m
// of a random point on a random triangle; a third of all quantised to the
// 2^-10 m state resolution (as real car positions are).
std::vector<Vec3> query_centres(std::mt19937_64& rng, const Track& track, int n) {
    std::vector<Vec3> out;
    out.reserve(static_cast<std::size_t>(n));
    const Vec3 pad(10, 10, 10);
    std::uniform_int_distribution<std::size_t> pick(0, track.triangles.size() - 1);
    for (int i = 0; i < n; ++i) {
        Vec3 p;
        if (i % 2 == 0) {
            p = random_in_box(rng, track.bounds.min - pad, track.bounds.max + pad);
        } else {
            const Triangle& t = track.triangles[pick(rng)];
            p = random_on_triangle(rng, t) + random_unit(rng) * uniform(rng, 0, 5);
        }
        if (i % 3 == 0) {
            for (int k = 0; k < 3; ++k) p[k] = quantize(p[k], kPosBits);
        }
        out.push_back(p);
    }
    return out;
}

struct GridReport {
    std::int64_t queries = 0;
    std::int64_t nonempty = 0;
    std::int64_t total_hits = 0;
};

// For every centre: the set of triangles within kQueryRadius found among the
// grid's candidates equals the brute-force set; the grid never reports a
// triangle twice; gather_candidates (sorted, used by the resolver) agrees.
void check_grid_against_brute(const Track& track, const std::vector<Vec3>& centres,
                              const std::vector<std::vector<std::uint32_t>>& brute, double cell_size,
                              GridReport& report) {
    const UniformGrid grid(track.triangles, track.bounds, 2.5, cell_size);
    SCOPED_TRACE("cell size " + std::to_string(grid.cell_size_m()) + " m (requested " + std::to_string(cell_size) +
                 "), dims " + std::to_string(grid.dims()[0]) + "x" + std::to_string(grid.dims()[1]) + "x" +
                 std::to_string(grid.dims()[2]));
    std::vector<std::uint32_t> stamp(track.triangles.size(), 0);
    std::vector<std::uint32_t> found;
    Candidates cand;
    const double r2 = kQueryRadius * kQueryRadius;
    int failures = 0;
    for (std::size_t qi = 0; qi < centres.size() && failures < 10; ++qi) {
        const Vec3& c = centres[qi];
        const auto mark = static_cast<std::uint32_t>(qi + 1);
        found.clear();
        int duplicates = 0;
        grid.for_each_candidate(Aabb::around(c, kQueryRadius), [&](std::uint32_t t) {
            if (stamp[t] == mark) {
                ++duplicates;
                return;
            }
            stamp[t] = mark;
            const Vec3 q = closest_point_on_triangle(c, track.triangles[t]).point;
            if ((c - q).squaredNorm() <= r2) found.push_back(t);
        });
        std::sort(found.begin(), found.end());
        if (duplicates != 0 || found != brute[qi]) {
            ++failures;
            std::ostringstream msg;
            msg << "query " << qi << " centre " << str(c) << ": " << duplicates << " duplicate candidates; grid found "
                << found.size() << ", brute force " << brute[qi].size() << "; missed:";
            std::vector<std::uint32_t> missed;
            std::set_difference(brute[qi].begin(), brute[qi].end(), found.begin(), found.end(),
                                std::back_inserter(missed));
            for (std::uint32_t m : missed) {
                const Triangle& t = track.triangles[m];
                msg << " #" << m << " " << str(t.a) << str(t.b) << str(t.c);
            }
            ADD_FAILURE() << msg.str();
            continue;
        }
        // The resolver's path: gather_candidates (sorted, ascending, no duplicates).
        gather_candidates(grid, track, Broadphase::grid, c, kQueryRadius, cand);
        if (!std::is_sorted(cand.triangles.begin(), cand.triangles.end()) ||
            std::adjacent_find(cand.triangles.begin(), cand.triangles.end()) != cand.triangles.end() ||
            !std::includes(cand.triangles.begin(), cand.triangles.end(), brute[qi].begin(), brute[qi].end())) {
            ++failures;
            ADD_FAILURE() << "gather_candidates at " << str(c) << " is unsorted, has duplicates or misses a triangle";
        }
        // ... and keeps exactly the triangles whose bounds reach the gathered
        // region, each with its bounds.
        std::vector<std::uint32_t> overlapping;
        const Vec3 slack(kBoxSlack_m, kBoxSlack_m, kBoxSlack_m);
        const Aabb region{cand.region.min - slack, cand.region.max + slack};
        for (std::uint32_t t = 0; t < track.triangles.size(); ++t) {
            if (track.triangles[t].bounds().overlaps(region)) overlapping.push_back(t);
        }
        if (cand.triangles != overlapping || cand.boxes.size() != cand.triangles.size()) {
            ++failures;
            ADD_FAILURE() << "gather_candidates at " << str(c) << " kept " << cand.triangles.size()
                          << " triangles; " << overlapping.size() << " have bounds overlapping the region";
        }
        ++report.queries;
        report.nonempty += brute[qi].empty() ? 0 : 1;
        report.total_hits += static_cast<std::int64_t>(brute[qi].size());
    }
    EXPECT_EQ(failures, 0);
}

void grid_matches_brute_force(const Track& track, const std::vector<double>& cell_sizes, int queries) {
    JETRACE_SEEDED_RNG(rng);
    const std::vector<Vec3> centres = query_centres(rng, track, queries);
    const BruteForce bf(track, kQueryRadius);
    std::vector<std::vector<std::uint32_t>> brute(centres.size());
    for (std::size_t i = 0; i < centres.size(); ++i) bf.within(centres[i], brute[i]);
    for (double cs : cell_sizes) {
        GridReport rep;
        check_grid_against_brute(track, centres, brute, cs, rep);
        EXPECT_EQ(rep.queries, static_cast<std::int64_t>(centres.size()));
        // The biased half must actually produce contacts, or the test proves little.
        EXPECT_GT(rep.nonempty, rep.queries / 5) << "too few queries touched any triangle";
        ::testing::Test::RecordProperty("nonempty_queries_cell_" + std::to_string(cs), std::to_string(rep.nonempty));
    }
}

// 2,000 random triangles of random sizes (0.1 to 60 m, log-uniform) in a
// 500 m box, with degenerate ones (collinear, two equal vertices, a single
// point), axis-aligned flat ones (zero-thickness boxes) and ones snapped to a
// 30 m or 37 m lattice so that their boxes sit exactly on cell boundaries of
// the 3, 10 and 37 m grids (the box's corners pin the grid origin at 0).
Track random_mesh(std::mt19937_64& rng, int count) {
    std::vector<Vec3> v;
    std::vector<std::uint32_t> idx;
    auto tri = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        const auto base = static_cast<std::uint32_t>(v.size());
        v.insert(v.end(), {a, b, c});
        idx.insert(idx.end(), {base, base + 1, base + 2});
    };
    auto clampv = [](const Vec3& p) -> Vec3 { return p.cwiseMax(Vec3(0, 0, 0)).cwiseMin(Vec3(500, 500, 500)); };
    auto snap = [](Vec3 p, double lattice) -> Vec3 {
        for (int k = 0; k < 3; ++k) p[k] = std::round(p[k] / lattice) * lattice;
        return p;
    };
    // Anchors: single-point triangles at two corners fix the bounds to [0, 500]^3.
    tri(Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 0));
    tri(Vec3(500, 500, 500), Vec3(500, 500, 500), Vec3(500, 500, 500));
    for (int i = 2; i < count; ++i) {
        const double size = std::exp(uniform(rng, std::log(0.1), std::log(60.0)));
        const Vec3 centre = random_in_box(rng, Vec3(0, 0, 0), Vec3(500, 500, 500));
        Vec3 a = clampv(centre + random_unit(rng) * (0.5 * size));
        Vec3 b = clampv(centre + random_unit(rng) * (0.5 * size));
        Vec3 c = clampv(centre + random_unit(rng) * (0.5 * size));
        switch (i % 20) {
            case 0: c = a + (b - a) * uniform(rng, -0.5, 1.5); c = clampv(c); break;  // collinear (nearly, after clamp)
            case 1: b = a; break;                                                   // two equal vertices
            case 2: b = a; c = a; break;                                            // a single point
            case 3: b.y() = a.y(); c.y() = a.y(); break;                            // flat, zero y thickness
            case 4: b.x() = a.x(); c.x() = a.x(); break;                            // vertical, zero x thickness
            case 5: a = snap(a, 30); b = snap(b + Vec3(30, 0, 0), 30); c = snap(c + Vec3(0, 0, 30), 30); break;
            case 6: a = snap(a, 37); b = snap(b + Vec3(37, 0, 0), 37); c = snap(c, 37); c.y() = a.y(); break;
            default: break;
        }
        tri(clampv(a), clampv(b), clampv(c));
    }
    return make_track("random", v, idx, {}, {}, -100);
}

}  // namespace

TEST(GridVsBruteForce, Stadium) {
    const Track track = make_oval(stadium_params());
    ASSERT_GT(track.triangles.size(), 1000u);
    // 0 = the documented default rule (10 m here). A 3 m grid over the
    // stadium's 1.7 km x 1 km x 0.4 km box would hold 25 million cells
    // (300 MB while building), so the finest explicit size here is 5 m; the
    // 3 m grid is exercised on the random mesh.
    grid_matches_brute_force(track, {0.0, 5.0, 10.0, 37.0}, 100'000);
}

TEST(GridVsBruteForce, RandomMesh) {
    JETRACE_SEEDED_RNG(mesh_rng);
    const Track track = random_mesh(mesh_rng, 2000);
    ASSERT_EQ(track.triangles.size(), 2000u);
    EXPECT_EQ(track.bounds.min, Vec3(0, 0, 0));
    EXPECT_EQ(track.bounds.max, Vec3(500, 500, 500));
    int degenerate = 0;
    for (const Triangle& t : track.triangles) degenerate += t.degenerate ? 1 : 0;
    EXPECT_GE(degenerate, 200) << "the mesh should contain degenerate triangles";
    grid_matches_brute_force(track, {0.0, 3.0, 10.0, 37.0}, 100'000);
}

TEST(GridVsBruteForce, CellSizeRule) {
    // The documented rule: the edge is 4 car radii whatever the track's
    // extent; only the key (at most 2^21 cells per axis) can grow it.
    const Track stadium = make_oval(stadium_params());
    EXPECT_EQ(UniformGrid::cell_size_for(stadium.bounds, 2.5), 10.0);
    const UniformGrid g(stadium.triangles, stadium.bounds, 2.5);
    EXPECT_EQ(g.cell_size_m(), 10.0);
    // cell_count() counts occupied cells only.
    EXPECT_GT(g.cell_count(), 0);
    EXPECT_LE(g.cell_count(), static_cast<std::int64_t>(g.entry_count()));
    // A 200 km box, and the largest box a track may span (2,000 km), keep 10 m cells.
    const Aabb huge{Vec3(-1e5, -1e3, -1e5), Vec3(1e5, 1e3, 1e5)};
    EXPECT_EQ(UniformGrid::cell_size_for(huge, 2.5), 10.0);
    const double m = kMaxTrackCoordinate_m;
    const Aabb largest{Vec3(-m, -m, -m), Vec3(m, m, m)};
    EXPECT_EQ(UniformGrid::cell_size_for(largest, 2.5), 10.0);
    // A radius too small for the key: the edge grows by factors of 1.0625
    // until every axis fits, and stops at the first that does.
    const double grown = UniformGrid::cell_size_for(largest, 1e-4);
    EXPECT_LE(std::floor(2 * m * (1.0 / grown)) + 1, UniformGrid::kMaxAxisCells);
    EXPECT_LE(grown, 1.0625 * 2 * m / (UniformGrid::kMaxAxisCells - 1) * (1 + 1e-9));
    // An explicit size is kept when the key allows it.
    EXPECT_EQ(UniformGrid(stadium.triangles, stadium.bounds, 2.5, 3.0).cell_size_m(), 3.0);
}

// ======================== sparse grid: wide tracks, against brute force

namespace {

// Five stadiums (at the corners and the centre) spread over `spread` times
// 54 km x 22 km, each shifted by a multiple of 10 m so that all sit alike on
// the 10 m lattice. With `rng`, also 3,000 small scattered triangles (0.1 to
// 30 m), 40 long thin ones (200 m to 3 km, hundreds of cells each) and 300
// snapped to the 10 m lattice (boxes on cell boundaries, some of zero
// thickness). Two single-point anchors pin the bounds, so the grid origin.
Track wide_sparse_track(std::mt19937_64* rng, double spread) {
    const Track one = make_oval(stadium_params());
    const double w = 54'000 * spread, d = 22'000 * spread;
    const Vec3 lo(-2000, -100, -1000), hi(w + 2000, 1200, d + 1000);  // the stadium: 1,580 x 1,033 x 380 m
    std::vector<Vec3> v;
    std::vector<std::uint32_t> idx;
    auto tri = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        const auto base = static_cast<std::uint32_t>(v.size());
        v.insert(v.end(), {a.cwiseMax(lo).cwiseMin(hi), b.cwiseMax(lo).cwiseMin(hi), c.cwiseMax(lo).cwiseMin(hi)});
        idx.insert(idx.end(), {base, base + 1, base + 2});
    };
    tri(lo, lo, lo);
    tri(hi, hi, hi);
    const Vec3 offsets[] = {Vec3(0, 0, 0), Vec3(w - 2000, 0, 0), Vec3(0, 0, d - 1000), Vec3(w - 2000, 0, d - 1000),
                            Vec3(std::round(w / 20) * 10, 0, std::round(d / 20) * 10)};
    for (const Vec3& off : offsets) {
        for (const Triangle& t : one.triangles) tri(t.a + off, t.b + off, t.c + off);
    }
    if (rng != nullptr) {
        std::mt19937_64& r = *rng;
        for (int i = 0; i < 3000; ++i) {
            const double size = std::exp(uniform(r, std::log(0.1), std::log(30.0)));
            const Vec3 c = random_in_box(r, lo, hi);
            tri(c + random_unit(r) * (0.5 * size), c + random_unit(r) * (0.5 * size), c + random_unit(r) * (0.5 * size));
        }
        for (int i = 0; i < 40; ++i) {
            const Vec3 a = random_in_box(r, lo, hi);
            const Vec3 along = i % 2 == 0 ? Vec3(1, 0, 0) : Vec3(0, 0, 1);
            const Vec3 b = a + along * uniform(r, 200, 3000);
            tri(a, b, b + Vec3(0, 0.5, 0) + random_unit(r) * 0.5);
        }
        for (int i = 0; i < 300; ++i) {
            Vec3 a = random_in_box(r, lo, hi);
            for (int k = 0; k < 3; ++k) a[k] = lo[k] + std::round((a[k] - lo[k]) / 10) * 10;
            const Vec3 b = a + Vec3(10.0 * (1 + i % 3), 0, 0);
            tri(a, b, i % 2 == 0 ? Vec3(a + Vec3(0, 0, 10)) : Vec3(a + Vec3(0, 10, 10)));
        }
    }
    return make_track("wide", v, idx, {}, {}, -1000);
}

// The documented bucketing, written out: a coordinate's cell along an axis,
// clamped to [0, dims - 1] (NaN to 0), from the grid's origin (the bounds'
// minimum) and edge.
struct Bucketing {
    Aabb bounds;
    double inv_cell;
    const std::int32_t* dims;
    std::int32_t coord(double v, int k) const {
        const double c = std::floor((v - bounds.min[k]) * inv_cell);
        if (!(c >= 0.0)) return 0;
        return c >= dims[k] - 1 ? dims[k] - 1 : static_cast<std::int32_t>(c);
    }
    CellRange range(const Aabb& b) const {
        CellRange r;
        for (int k = 0; k < 3; ++k) {
            r.lo[k] = coord(b.min[k], k);
            r.hi[k] = coord(b.max[k], k);
        }
        return r;
    }
    std::uint64_t key(std::int32_t x, std::int32_t y, std::int32_t z) const {
        const auto u = [](std::int32_t v) { return static_cast<std::uint64_t>(v); };
        return (u(z) * u(dims[1]) + u(y)) * u(dims[0]) + u(x);
    }
};

bool ranges_overlap(const CellRange& a, const CellRange& b) {
    for (int k = 0; k < 3; ++k) {
        if (a.lo[k] > b.hi[k] || b.lo[k] > a.hi[k]) return false;
    }
    return true;
}

// `queries` random boxes (car-sized and up to 120 m, some flat, some beyond
// the bounds, a few with NaN): for_each_candidate reports exactly the
// triangles whose bucket overlaps the box's cell range, each once, in
// ascending (owner cell, triangle) order; cell_range agrees with the
// written-out bucketing.
void sparse_grid_matches_brute_force(const Track& track, const UniformGrid& grid, const Aabb& grid_bounds,
                                     std::mt19937_64& rng, int queries, int min_nonempty) {
    const Bucketing ref{grid_bounds, 1.0 / grid.cell_size_m(), grid.dims()};
    const std::size_t n = track.triangles.size();
    std::vector<CellRange> bucket(n);
    for (std::size_t t = 0; t < n; ++t) bucket[t] = ref.range(track.triangles[t].bounds());
    std::uniform_int_distribution<std::size_t> pick(0, n - 1);
    const Vec3 pad(200, 50, 200);
    std::vector<std::uint32_t> got, want;
    int failures = 0, nonempty = 0;
    for (int i = 0; i < queries && failures < 10; ++i) {
        Vec3 c = random_in_box(rng, track.bounds.min - pad, track.bounds.max + pad);
        if (i % 2 == 1) c = random_on_triangle(rng, track.triangles[pick(rng)]) + random_unit(rng) * uniform(rng, 0, 8);
        if (i % 3 == 0) {
            for (int k = 0; k < 3; ++k) c[k] = quantize(c[k], kPosBits);
        }
        const double h = i % 4 == 0 ? uniform(rng, 0, 60) : (i % 4 == 1 ? 3.5 : kQueryRadius);
        Aabb box = Aabb::around(c, h);
        if (i % 7 == 0) box.max.y() = box.min.y();                     // flat
        if (i % 11 == 0) box.max += Vec3(uniform(rng, 0, 60), 0, 0);  // long
        if (i % 997 == 0) box.min.z() = std::numeric_limits<double>::quiet_NaN();
        const bool inside = box.overlaps(grid_bounds);
        const CellRange q = ref.range(box);
        CellRange g{};
        if (grid.cell_range(box, g) != inside ||
            (inside && !std::equal(std::begin(g.lo), std::end(g.lo), std::begin(q.lo))) ||
            (inside && !std::equal(std::begin(g.hi), std::end(g.hi), std::begin(q.hi)))) {
            ++failures;
            ADD_FAILURE() << "query " << i << ": cell_range disagrees with the bucketing for " << str(box.min)
                          << str(box.max);
            continue;
        }
        got.clear();
        bool ordered = true;
        std::uint64_t last_owner = 0;
        std::uint32_t last_tri = 0;
        grid.for_each_candidate(box, [&](std::uint32_t t) {
            const CellRange& r = bucket[t];
            const std::uint64_t owner = ref.key(std::max(r.lo[0], q.lo[0]), std::max(r.lo[1], q.lo[1]),
                                                std::max(r.lo[2], q.lo[2]));
            if (!got.empty() && (owner < last_owner || (owner == last_owner && t <= last_tri))) ordered = false;
            last_owner = owner;
            last_tri = t;
            got.push_back(t);
        });
        want.clear();
        if (inside) {
            for (std::size_t t = 0; t < n; ++t) {
                if (ranges_overlap(bucket[t], q)) want.push_back(static_cast<std::uint32_t>(t));
            }
        }
        std::vector<std::uint32_t> sorted = got;
        std::sort(sorted.begin(), sorted.end());
        const bool unique = std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
        if (sorted != want || !unique || !ordered) {
            ++failures;
            ADD_FAILURE() << "query " << i << " box " << str(box.min) << str(box.max) << ": grid reported "
                          << got.size() << " (" << (unique ? "unique" : "with duplicates") << ", "
                          << (ordered ? "in order" : "out of order") << "), brute force " << want.size();
        }
        nonempty += want.empty() ? 0 : 1;
    }
    EXPECT_EQ(failures, 0);
    // The biased half must actually meet triangles, or the test proves little.
    EXPECT_GE(nonempty, min_nonempty);
    ::testing::Test::RecordProperty("nonempty_of_" + std::to_string(queries) + "_queries", std::to_string(nonempty));
}

}  // namespace

TEST(SparseGrid, MatchesBruteForceOnWideSparseTrack) {
    JETRACE_SEEDED_RNG(rng);
    const Track track = wide_sparse_track(&rng, 1.0);
    ASSERT_EQ(track.triangles.size(), 2 + 5 * 1384u + 3340);
    const UniformGrid grid(track.triangles, track.bounds, 2.5);
    ASSERT_EQ(grid.cell_size_m(), 10.0);
    sparse_grid_matches_brute_force(track, grid, track.bounds, rng, 4000, 1400);
    // Bounds smaller than the mesh: buckets and queries clamp to the edge
    // cells, which then hold many triangles; each is still reported once.
    const Aabb shrunk{track.bounds.min + Vec3(2500, 0, 1200), track.bounds.max - Vec3(2500, 600, 1200)};
    const UniformGrid clamped(track.triangles, shrunk, 2.5);
    sparse_grid_matches_brute_force(track, clamped, shrunk, rng, 2000, 300);
}

TEST(SparseGrid, CellEdgeStaysFourRadiiAndMemoryFollowsEntries) {
    // Five stadiums over 54 km x 22 km, then the same over 108 km x 44 km.
    const Track near = wide_sparse_track(nullptr, 1.0);
    const Track far = wide_sparse_track(nullptr, 2.0);
    const UniformGrid a(near.triangles, near.bounds, 2.5);
    const UniformGrid b(far.triangles, far.bounds, 2.5);
    for (const UniformGrid* g : {&a, &b}) {
        const double dense_cells = double(g->dims()[0]) * g->dims()[1] * g->dims()[2];
        SCOPED_TRACE("dims " + std::to_string(g->dims()[0]) + "x" + std::to_string(g->dims()[1]) + "x" +
                     std::to_string(g->dims()[2]) + ", " + std::to_string(g->cell_count()) + " occupied cells, " +
                     std::to_string(g->entry_count()) + " entries, " + std::to_string(g->memory_bytes()) + " bytes");
        EXPECT_EQ(g->cell_size_m(), 10.0);
        EXPECT_GT(dense_cells, 5e8);
        EXPECT_LE(g->cell_count(), static_cast<std::int64_t>(g->entry_count()));
        // 4 bytes per pair, at most 32 per occupied cell (4-byte hash slots
        // at load >= 1/4, 16-byte cell record) and 12 per triangle (its
        // lowest cell).
        EXPECT_LE(g->memory_bytes(), 4 * g->entry_count() + 32 * std::size_t(g->cell_count()) +
                                         12 * near.triangles.size() + 32);
        // A dense grid's offsets alone would take 4 bytes per cell.
        EXPECT_LT(double(g->memory_bytes()), 4 * dense_cells / 1000);
    }
    // Four times the area, the same memory: it follows the occupied cells.
    EXPECT_EQ(a.entry_count(), b.entry_count());
    EXPECT_EQ(a.cell_count(), b.cell_count());
    EXPECT_EQ(a.memory_bytes(), b.memory_bytes());
}

TEST(SparseGrid, HugeTrianglesGrowTheEdgeWithinThePairBudget) {
    // A ground quad over the largest area a track may span: 4e10 cells of
    // 10 m each, so the edge grows until the pairs fit the budget.
    const double m = kMaxTrackCoordinate_m;
    const std::vector<Vec3> v = {Vec3(-m, 0, -m), Vec3(-m, 0, m), Vec3(m, 0, m), Vec3(m, 0, -m)};
    const Track ground = make_track("ground", v, {0, 1, 2, 0, 2, 3}, {}, {}, -100);
    const UniformGrid g(ground.triangles, ground.bounds, 2.5);
    EXPECT_GT(g.cell_size_m(), 10.0);
    EXPECT_LE(static_cast<std::int64_t>(g.entry_count()), UniformGrid::entry_budget(2));
    std::vector<std::uint32_t> got;
    const Aabb car = Aabb::around(Vec3(123.4, 1, -4567.8), kQueryRadius);
    g.for_each_candidate(car, [&](std::uint32_t t) { got.push_back(t); });
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, (std::vector<std::uint32_t>{0, 1}));
}

// ================================= seed regression: planes must be found

namespace {

// A square of half-size L on a plane through `origin` tilted by `deg` about
// the Z axis (0 = the flat floor y = origin.y), as two triangles (normal up).
struct Plane {
    Track track;
    Vec3 along;   // unit, in the plane, perpendicular to Z
    Vec3 normal;  // unit, upward
    Vec3 origin;
};

Plane tilted_plane(double deg, const Vec3& origin, double L, std::vector<Vec3> extra_points = {}) {
    const double th = deg * kPi / 180.0;
    Plane p;
    // Exact axes for 0 and 90 degrees (zero-thickness boxes).
    p.along = deg == 0.0 ? Vec3(1, 0, 0) : deg == 90.0 ? Vec3(0, 1, 0) : Vec3(std::cos(th), std::sin(th), 0);
    p.normal = deg == 0.0 ? Vec3(0, 1, 0) : deg == 90.0 ? Vec3(-1, 0, 0) : Vec3(-std::sin(th), std::cos(th), 0);
    p.origin = origin;
    const Vec3 z(0, 0, 1);
    std::vector<Vec3> v = {origin - p.along * L - z * L, origin - p.along * L + z * L, origin + p.along * L + z * L,
                           origin + p.along * L - z * L};
    std::vector<std::uint32_t> idx = {0, 1, 2, 0, 2, 3};
    // Extra single-point triangles enlarge the bounds (to move the plane onto
    // an interior cell boundary).
    for (const Vec3& e : extra_points) {
        const auto base = static_cast<std::uint32_t>(v.size());
        v.insert(v.end(), {e, e, e});
        idx.insert(idx.end(), {base, base + 1, base + 2});
    }
    p.track = make_track("plane", v, idx, {}, {}, -1e4);
    return p;
}

// Spheres resting on / touching / slightly in / within the skin of the plane
// at random places: the grid reports the plane's triangle(s) and
// find_contacts (through gather_candidates, both broadphases) reports a
// contact along the plane normal.
void plane_is_found(const Plane& plane, double L, double cell_size, std::mt19937_64& rng) {
    const PhysicsSettings ps;
    const double r = ps.car_radius_m;
    const UniformGrid grid(plane.track.triangles, plane.track.bounds, r, cell_size);
    SCOPED_TRACE("cell " + std::to_string(grid.cell_size_m()) + " m, dims " + std::to_string(grid.dims()[0]) + "x" +
                 std::to_string(grid.dims()[1]) + "x" + std::to_string(grid.dims()[2]));
    const double offsets[] = {r, r + ps.resolver_epsilon_m, r + 0.5 * ps.contact_skin_m, r - 0.01, r - 0.5};
    const Vec3 z(0, 0, 1);
    Candidates cand;
    Contacts contacts;
    int failures = 0;
    for (int i = 0; i < 2000 && failures < 5; ++i) {
        const Vec3 foot = plane.origin + plane.along * uniform(rng, -0.9 * L, 0.9 * L) + z * uniform(rng, -0.9 * L, 0.9 * L);
        const double off = offsets[i % 5];
        Vec3 c = foot + plane.normal * off;
        if (i % 2 == 0) {
            for (int k = 0; k < 3; ++k) c[k] = quantize(c[k], kPosBits);  // state resolution
        }
        // The foot is well inside the square: the distance to it is the distance to its plane.
        const double d = std::abs((c - plane.origin).dot(plane.normal));
        ASSERT_LT(d, r + ps.contact_skin_m - 1e-4);
        bool got[2] = {false, false};
        int count = 0;
        grid.for_each_candidate(Aabb::around(c, r + ps.contact_skin_m), [&](std::uint32_t t) {
            if (t < 2) got[t] = true;
            ++count;
        });
        for (std::uint32_t t = 0; t < 2; ++t) {
            const Vec3 q = closest_point_on_triangle(c, plane.track.triangles[t]).point;
            if ((c - q).norm() <= r + ps.contact_skin_m && !got[t]) {
                ++failures;
                ADD_FAILURE() << "grid misses plane triangle " << t << " at distance " << (c - q).norm() << " from "
                              << str(c) << " (offset " << off << ")";
            }
        }
        for (Broadphase bp : {Broadphase::grid, Broadphase::brute_force}) {
            gather_candidates(grid, plane.track, bp, c, r + ps.contact_skin_m + 0.5, cand);
            find_contacts(plane.track, cand, ps, c, contacts);
            bool along_normal = false;
            for (int k = 0; k < contacts.count; ++k) along_normal |= (contacts.normal[k] - plane.normal).norm() < 1e-9;
            if (!along_normal) {
                ++failures;
                ADD_FAILURE() << "find_contacts (" << (bp == Broadphase::grid ? "grid" : "brute force")
                              << ") has no contact along the plane normal at " << str(c) << " (offset " << off
                              << ", " << contacts.count << " contacts)";
            }
        }
    }
}

}  // namespace

// The seed's second bug: a car resting on or touching a surface must be found
// by the grid whatever the surface's slope, including an axis-aligned floor
// whose bounding box has zero thickness, and including a floor lying exactly
// on a cell boundary.
TEST(GridRegression, InclinedAndFlatPlanesAreFound) {
    JETRACE_SEEDED_RNG(rng);
    const double L = 60.0;
    for (double deg : {0.0, 30.0, 60.0}) {
        SCOPED_TRACE("slope " + std::to_string(deg) + " degrees");
        const Plane plane = tilted_plane(deg, Vec3(0, 0, 0), L);
        if (deg == 0.0) {
            ASSERT_EQ(plane.track.bounds.min.y(), plane.track.bounds.max.y()) << "floor box should be flat";
        }
        for (double cs : {0.0, 3.0, 10.0, 37.0}) plane_is_found(plane, L, cs, rng);
    }
    // A flat floor at y = 20 with the track's bounds starting at y = 0, so the
    // floor lies exactly on a cell boundary of the 10 m (and default) grid.
    const Plane raised = tilted_plane(0.0, Vec3(0, 20, 0), L, {Vec3(0, 0, 0)});
    ASSERT_EQ(raised.track.bounds.min.y(), 0.0);
    for (double cs : {0.0, 5.0, 10.0, 20.0}) plane_is_found(raised, L, cs, rng);
    // A vertical wall (zero thickness along X) lying on a cell boundary.
    const Plane wall = tilted_plane(90.0, Vec3(30, 0, 0), L, {Vec3(-30, 0, 0)});
    for (double cs : {0.0, 6.0, 10.0, 30.0}) plane_is_found(wall, L, cs, rng);
}

// A car at rest on a flat floor, stepped through the whole world: it stays in
// contact (grounded: thrust moves it along the floor) instead of being treated
// as airborne.
TEST(GridRegression, CarAtRestOnZeroThicknessFloorIsGrounded) {
    std::vector<Vec3> v = {Vec3(-100, 0, -100), Vec3(-100, 0, 100), Vec3(100, 0, 100), Vec3(100, 0, -100)};
    std::vector<std::uint32_t> idx = {0, 1, 2, 0, 2, 3};
    const Pose spawn{Vec3(0, 2.5 + 1.0 / 1024.0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    Checkpoint g0;
    g0.center = Vec3(5000, 10, 0);
    g0.normal = Vec3(1, 0, 0);
    g0.across = Vec3(0, 0, 1);
    g0.respawn = spawn;
    Checkpoint g1 = g0;
    g1.center = Vec3(-5000, 10, 0);
    g1.normal = Vec3(-1, 0, 0);
    g1.across = Vec3(0, 0, -1);
    const Scene scene = Scene::make(make_track("floor", v, idx, {g0, g1}, {spawn}, -100), PhysicsSettings{});
    ASSERT_EQ(scene.track.bounds.min.y(), scene.track.bounds.max.y());
    WorldState st = make_world(1, 1);
    spawn_car(scene, st, 0, 0);
    StepScratch scratch;
    const Input go = Input::clamped(Input::kMaxThrottle, 0, 0);
    for (int i = 0; i < 60; ++i) step(scene, st, std::span<const Input>(&go, 1), scratch);
    // Half a second of full thrust on the floor: about 12 m/s, and still on it.
    EXPECT_GT(st.cars[0].velocity.x(), 10.0);
    EXPECT_NEAR(st.cars[0].position.y(), 2.5 + 1.0 / 1024.0, 1e-3);
}
