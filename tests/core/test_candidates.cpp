// What makes a car's candidates cheap to scan must not change what a scan
// finds: the run and group boxes against the one-by-one box test, the
// float boxes the grid keeps against the exact bounds, a kept
// TriangleFrame against computing it each time (bit for bit), and the
// closest-point test's rejections against the exact distance.
//
// Random tests draw from std::mt19937_64. The seed is fixed by default; set
// the environment variable JETRACE_TEST_SEED (decimal or 0x-hex) to run with
// another one. Every random test prints the seed it used on failure
// (SCOPED_TRACE) and records it as the test property "seed", so a failure
// can be replayed with
//   JETRACE_TEST_SEED=<seed> ./test_candidates --gtest_filter=<test>
#include "jetrace/core/candidates.hpp"
#include "jetrace/core/geometry.hpp"
#include "jetrace/core/resolver.hpp"

#include "support/random_geometry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

using namespace jetrace;
using namespace jetrace::test;

namespace {

// `n` boxes along a winding strip (neighbours near each other, as a mesh
// lists them), every few a far one, so that runs are tight but not all.
// `exact` receives the boxes in doubles.
Candidates strip_of_boxes(std::mt19937_64& rng, std::size_t n, std::vector<Aabb>* exact = nullptr) {
    Candidates c;
    std::vector<FloatBox> float_boxes;
    const Vec3 start = random_in_box(rng, Vec3(-900, -50, -900), Vec3(900, 50, 900));
    Vec3 at = start;
    for (std::size_t k = 0; k < n; ++k) {
        at += Vec3(uniform(rng, -1.5, 1.5), uniform(rng, -0.3, 0.3), uniform(rng, -1.5, 1.5));
        const Vec3 centre = k % 13 == 7 ? start + random_in_box(rng, Vec3(-80, -20, -80), Vec3(80, 20, 80)) : at;
        const Vec3 half(uniform(rng, 0, 1.5), uniform(rng, 0, 0.5), uniform(rng, 0, 1.5));
        c.triangles.push_back(static_cast<std::uint32_t>(k));
        float_boxes.push_back(FloatBox::around(Aabb{centre - half, centre + half}));
        if (exact != nullptr) exact->push_back(float_boxes.back().aabb());
    }
    c.finish_gather([&](std::uint32_t t) -> const FloatBox& { return float_boxes[t]; });
    return c;
}

// Every candidate from k on that may_touch accepts, one by one.
std::vector<std::size_t> one_by_one(const Candidates& c, std::size_t from, const Vec3& p, double reach) {
    std::vector<std::size_t> out;
    for (std::size_t k = from; k < c.boxes.size(); ++k) {
        if (c.may_touch(k, p, reach)) out.push_back(k);
    }
    return out;
}

std::vector<std::size_t> by_runs(const Candidates& c, std::size_t from, const Vec3& p, double reach) {
    const std::size_t count = c.touching_from(from, p, reach);
    return std::vector<std::size_t>(c.found.begin(), c.found.begin() + static_cast<std::ptrdiff_t>(count));
}

// A point near candidate k's box.
Vec3 near_box(std::mt19937_64& rng, const Candidates& c, std::size_t k) {
    return c.boxes.box(k).aabb().min + random_unit(rng) * uniform(rng, 0, 6);
}

}  // namespace

TEST(Candidates, RunsFindExactlyWhatTheOneByOneTestFinds) {
    JETRACE_SEEDED_RNG(rng);
    int failures = 0, found = 0;
    // Lengths around the run (8) and group (64) sizes, and longer.
    for (const std::size_t n : {0u, 1u, 7u, 8u, 9u, 63u, 64u, 65u, 130u, 517u}) {
        const Candidates c = strip_of_boxes(rng, n);
        ASSERT_EQ(c.runs.size(), (n + Candidates::kRunLength - 1) / Candidates::kRunLength);
        ASSERT_EQ(c.groups.size(), (n + (std::size_t{1} << Candidates::kGroupShift) - 1) >> Candidates::kGroupShift);
        for (int q = 0; q < 400 && failures < 10; ++q) {
            Vec3 p = n == 0 ? Vec3(0, 0, 0) : near_box(rng, c, static_cast<std::size_t>(q) % n);
            if (q % 97 == 0) p.y() = std::numeric_limits<double>::quiet_NaN();
            const double reach = q % 5 == 0 ? uniform(rng, 0, 0.01) : uniform(rng, 0.5, 4);
            // From the start, or from a candidate on (a pass after a push).
            const std::size_t from = q % 3 == 0 ? static_cast<std::size_t>(uniform(rng, 0, static_cast<double>(n + 1))) : 0;
            const std::vector<std::size_t> want = one_by_one(c, std::min(from, n), p, reach);
            found += want.empty() ? 0 : 1;
            if (by_runs(c, std::min(from, n), p, reach) != want) {
                ++failures;
                ADD_FAILURE() << n << " candidates, query " << q << " from " << from << " at " << str(p) << " reach "
                              << reach << ": touching_from differs from may_touch";
            }
        }
    }
    EXPECT_EQ(failures, 0);
    EXPECT_GT(found, 1000) << "queries should meet boxes";
}

// The packed test works in floats. It must accept every box whose exact
// distance (in doubles) is within the reach plus kBoxSlack_m, and may
// accept only a little more (2^-22 of the point's coordinates, 20 um at
// most beside that): the strip lies up to 1 km from the world's origin,
// reaches go from none to a sweep's.
TEST(Candidates, BoxTestsAcceptEveryBoxWithinReachAndLittleMore) {
    JETRACE_SEEDED_RNG(rng);
    std::vector<Aabb> exact;
    const Candidates c = strip_of_boxes(rng, 400, &exact);
    int misses = 0, extras = 0, near_edge = 0;
    for (int q = 0; q < 20000 && misses < 10; ++q) {
        const std::size_t k = static_cast<std::size_t>(q) % exact.size();
        const double reach = q % 4 == 0 ? uniform(rng, 0, 0.05) : uniform(rng, 0.5, 40);
        // Points at about the reach from the box, where rounding decides.
        const Vec3 corner = q % 2 == 0 ? exact[k].min : exact[k].max;
        const Vec3 p = corner + random_unit(rng) * (reach + uniform(rng, -1e-5, 1e-5));
        const double d = std::sqrt(box_distance2(exact[k], p.x(), p.y(), p.z()));
        const bool accepted = c.may_touch(k, p, reach);
        const bool axes = c.may_reach_along_axes(k, c.box_query(p, reach));
        const double h = reach + kBoxSlack_m;
        near_edge += std::abs(d - h) < 1e-5 ? 1 : 0;
        if (d <= h && !accepted) {
            ++misses;
            ADD_FAILURE() << "box " << k << " at " << d << " m rejected at reach " << reach;
        }
        if (d <= h && !axes) {
            ++misses;
            ADD_FAILURE() << "box " << k << " at " << d << " m rejected along the axes at reach " << reach;
        }
        const double far = std::max({std::abs(p.x()), std::abs(p.y()), std::abs(p.z())});
        if (accepted && d > h + far * 0x1p-22 + 2e-5) ++extras;
    }
    EXPECT_EQ(misses, 0);
    EXPECT_EQ(extras, 0) << "boxes accepted farther beyond reach than the rounding allows";
    EXPECT_GT(near_edge, 1000) << "the points should test the rounding";
}

TEST(Candidates, RunBoxesAreTheBoxesAroundTheirCandidates) {
    JETRACE_SEEDED_RNG(rng);
    const Candidates c = strip_of_boxes(rng, 300);
    // The smallest box around boxes[first, first + count).
    const auto around = [&](std::size_t first, std::size_t count) {
        FloatBox b = c.boxes.box(first);
        for (std::size_t k = first + 1; k < std::min(c.boxes.size(), first + count); ++k) b.expand(c.boxes.box(k));
        return b;
    };
    const auto same = [](const FloatBox& a, const FloatBox& b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    for (std::size_t r = 0; r < c.runs.size(); ++r) {
        EXPECT_TRUE(same(c.runs.box(r), around(r * Candidates::kRunLength, Candidates::kRunLength))) << "run " << r;
    }
    const std::size_t per_group = std::size_t{1} << Candidates::kGroupShift;
    for (std::size_t g = 0; g < c.groups.size(); ++g) {
        EXPECT_TRUE(same(c.groups.box(g), around(g * per_group, per_group))) << "group " << g;
    }
}

TEST(FloatBox, AroundIsTheSmallestFloatBoxHoldingTheBox) {
    JETRACE_SEEDED_RNG(rng);
    const float inf = std::numeric_limits<float>::infinity();
    for (int i = 0; i < 20000; ++i) {
        const double scale = std::exp(uniform(rng, std::log(1e-3), std::log(2e6)));
        Vec3 lo = random_in_box(rng, Vec3(-1, -1, -1), Vec3(1, 1, 1)) * scale;
        if (i % 10 == 0) lo = lo.cast<float>().cast<double>();  // already floats
        const Vec3 hi = lo + Vec3(uniform(rng, 0, 3), 0, uniform(rng, 0, 1e-9));
        const FloatBox f = FloatBox::around(Aabb{lo, hi});
        const Aabb back = f.aabb();
        for (int k = 0; k < 3; ++k) {
            ASSERT_LE(back.min[k], lo[k]) << i;
            ASSERT_GE(back.max[k], hi[k]) << i;
            // One float inward would no longer hold it.
            ASSERT_GT(double{std::nextafter(f.lo[k], inf)}, lo[k]) << i;
            ASSERT_LT(double{std::nextafter(f.hi[k], -inf)}, hi[k]) << i;
        }
    }
    // Beyond the float range: the largest float, or infinity.
    const FloatBox huge = FloatBox::around(Aabb{Vec3(1e39, -1e39, 0), Vec3(1e39, -1e39, 0)});
    EXPECT_EQ(huge.lo[0], std::numeric_limits<float>::max());
    EXPECT_EQ(huge.hi[0], inf);
    EXPECT_EQ(huge.lo[1], -inf);
    EXPECT_EQ(huge.hi[1], -std::numeric_limits<float>::max());
}

TEST(TriangleFrame, KeptFrameGivesTheSameBitsAsComputingIt) {
    JETRACE_SEEDED_RNG(rng);
    int compared = 0;
    for (int k = 0; k < 300; ++k) {
        const double size = std::exp(uniform(rng, std::log(0.05), std::log(60.0)));
        const Vec3 at = random_in_box(rng, Vec3(-1000, -100, -1000), Vec3(1000, 100, 1000));
        Triangle t = Triangle::make(at + random_unit(rng) * size, at + random_unit(rng) * size,
                                    at + random_unit(rng) * size);
        if (k % 10 == 0) t = Triangle::make(at, at + Vec3(size, 0, 0), at + Vec3(size, 1e-5 * size, 0));  // sliver
        if (t.degenerate) continue;
        const TriangleFrame frame = TriangleFrame::of(t);
        for (int q = 0; q < 200; ++q) {
            const Vec3 p = random_on_triangle(rng, t) + random_unit(rng) * uniform(rng, 0, 2 * size + 3);
            const double reach = uniform(rng, 0, 2 * size + 3);
            ClosestPoint a, b;
            const bool ra = closest_point_within(p, t, reach, a);
            const bool rb = closest_point_within(p, t, frame, reach, b);
            ASSERT_EQ(ra, rb) << "triangle " << k << " point " << str(p);
            if (!ra) continue;
            ++compared;
            ASSERT_EQ(std::memcmp(a.point.data(), b.point.data(), sizeof(double) * 3), 0) << "triangle " << k;
            ASSERT_EQ(a.region, b.region) << "triangle " << k;
        }
    }
    EXPECT_GT(compared, 10000);
}

TEST(FrameCache, GivesEachTrianglesOwnFrameWhateverSharesItsSlot) {
    JETRACE_SEEDED_RNG(rng);
    // More triangles than slots, asked for in a random order, so that slots
    // are shared and refilled.
    std::vector<Triangle> triangles;
    for (int k = 0; k < 3 * static_cast<int>(FrameCache::kSlots); ++k) {
        const Vec3 at = random_in_box(rng, Vec3(-100, -10, -100), Vec3(100, 10, 100));
        const Triangle t = Triangle::make(at, at + random_unit(rng) * 3.0, at + random_unit(rng) * 3.0);
        if (!t.degenerate) triangles.push_back(t);
    }
    FrameCache cache;
    for (int q = 0; q < 5000; ++q) {
        const auto i = static_cast<std::uint32_t>(uniform(rng, 0, static_cast<double>(triangles.size())));
        const std::uint32_t index = std::min<std::uint32_t>(i, static_cast<std::uint32_t>(triangles.size() - 1));
        const TriangleFrame want = TriangleFrame::of(triangles[index]);
        const TriangleFrame& got = cache.get(index, triangles[index]);
        ASSERT_EQ(std::memcmp(&want, &got, sizeof want), 0) << "triangle " << index << " query " << q;
    }
}

TEST(ClosestPointWithin, RejectsOnlyTrianglesBeyondReach) {
    JETRACE_SEEDED_RNG(rng);
    int rejected_near_plane = 0, accepted = 0;  // rejected_near_plane: by plane and edge together
    for (int k = 0; k < 300; ++k) {
        const double size = std::exp(uniform(rng, std::log(0.05), std::log(60.0)));
        const Vec3 at = random_in_box(rng, Vec3(-1000, -100, -1000), Vec3(1000, 100, 1000));
        Triangle t = Triangle::make(at + random_unit(rng) * size, at + random_unit(rng) * size,
                                    at + random_unit(rng) * size);
        if (k % 10 == 0) {
            // A sliver at an angle to the axes, height 1e-9 to 1e-4 of its
            // length: its computed normal is as poor as they come.
            const Vec3 along = random_unit(rng);
            const Vec3 across = along.cross(random_unit(rng)).normalized();
            const double height = std::exp(uniform(rng, std::log(1e-9), std::log(1e-4))) * size;
            t = Triangle::make(at, at + along * size, at + along * (0.5 * size) + across * height);
        }
        if (t.degenerate) continue;
        const Vec3 n = t.normal();
        for (int q = 0; q < 200; ++q) {
            // Over the triangle's plane near it, as a car over a mesh is:
            // within reach of the plane and of every edge's line, often not
            // of the triangle.
            const double reach = uniform(rng, 0.01, 2 * size + 3);
            const Vec3 p = random_on_triangle(rng, t) + random_unit(rng) * uniform(rng, 0, 2 * reach) +
                           n * uniform(rng, -reach, reach);
            ClosestPoint got;
            const bool within = closest_point_within(p, t, reach, got);
            const ClosestPoint exact = closest_point_on_triangle(p, t);
            // What callers compare: the squared distance against reach^2.
            const double d2 = (p - exact.point).squaredNorm();
            if (!within) {
                ASSERT_GT(d2, reach * reach) << "triangle " << k << (t.thin ? " (thin)" : "") << " point " << str(p)
                                             << " reach " << reach << ": rejected within reach";
                // Within reach of the plane and of every edge's line: only
                // the test on both together can reject it.
                const bool near_lines = (p - t.a).dot(t.inward(0, n)) >= -reach &&
                                        (p - t.b).dot(t.inward(1, n)) >= -reach &&
                                        (p - t.c).dot(t.inward(2, n)) >= -reach;
                if (std::abs((p - t.a).dot(n)) <= reach && near_lines) ++rejected_near_plane;
                continue;
            }
            ++accepted;
            ASSERT_EQ(std::memcmp(got.point.data(), exact.point.data(), sizeof(double) * 3), 0) << "triangle " << k;
            ASSERT_EQ(got.region, exact.region) << "triangle " << k;
        }
    }
    EXPECT_GT(rejected_near_plane, 1000) << "the edge-and-plane rejection should fire";
    EXPECT_GT(accepted, 1000);
}

TEST(ClosestPointWithin, KeepsASliverWithinReach) {
    // A sliver (height about 2e-10 of its length) whose computed normal is
    // off by enough that the plane-and-edge lower bound overshoots the
    // distance by micrometres: the point is within reach (by about 1e-14 m)
    // and must not be rejected.
    const Triangle t = Triangle::make(Vec3(-970.3963625692855, -4.305578389483884, -665.7665279558566),
                                      Vec3(-956.0825310796574, -40.98860557198981, -688.9914068730758),
                                      Vec3(-960.8251050987143, -28.834489313130053, -681.2963527825094));
    ASSERT_FALSE(t.degenerate);
    ASSERT_TRUE(t.thin);
    const Vec3 p(-961.338177959928, -28.14028879745202, -681.8199828808672);
    const double reach = 0.9029648765833164;
    const ClosestPoint exact = closest_point_on_triangle(p, t);
    ASSERT_LE((p - exact.point).squaredNorm(), reach * reach);
    ClosestPoint got, with_frame;
    EXPECT_TRUE(closest_point_within(p, t, reach, got));
    EXPECT_TRUE(closest_point_within(p, t, TriangleFrame::of(t), reach, with_frame));
}
