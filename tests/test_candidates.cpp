// The candidates' scans: BoxColumns' paired distance test against a plain
// one, and Candidates::next_touching (through its focus) against a scan of
// every box with may_touch, for a car wandering through a gathered region so
// that focuses are both reused and made again.
//
// Random tests: JETRACE_TEST_SEED=<seed> ./test_candidates repeats a run.
#include "jetrace/box_columns.hpp"
#include "jetrace/candidates.hpp"

#include "support/test_seed.hpp"
#include "support/vec_str.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

using namespace jetrace;
using namespace jetrace::test;

namespace {

// The reference: the squared distance from p to box b, axis by axis.
bool plain_within(const Aabb& b, const Vec3& p, double h2) {
    double d2 = 0.0;
    for (int i = 0; i < 3; ++i) {
        const double d = std::max(std::max(b.min[i] - p[i], p[i] - b.max[i]), 0.0);
        d2 += d * d;
    }
    return d2 <= h2;
}

Aabb random_box(std::mt19937_64& rng, double spread_m) {
    std::uniform_real_distribution<double> at(-spread_m, spread_m), size(0.0, 3.0);
    const Vec3 lo(at(rng), at(rng), at(rng));
    return {lo, lo + Vec3(size(rng), size(rng) * 0.2, size(rng))};
}

TEST(BoxColumns, FindsTheBoxesAPlainDistanceTestFindsAtEveryCountAndStart) {
    JETRACE_SEEDED_RNG(rng);
    std::uniform_real_distribution<double> at(-6.0, 6.0), reach(0.0, 4.0);
    for (int n = 0; n <= 9; ++n) {
        std::vector<Aabb> boxes;
        BoxColumns cols;
        for (int k = 0; k < n; ++k) {
            boxes.push_back(random_box(rng, 5.0));
            cols.push(boxes.back());
        }
        ASSERT_EQ(cols.size(), boxes.size());
        for (int trial = 0; trial < 200; ++trial) {
            const Vec3 p(at(rng), at(rng), at(rng));
            const double h2 = reach(rng) * reach(rng);
            std::vector<std::size_t> expected, seen;
            for (std::size_t k = 0; k < boxes.size(); ++k) {
                if (plain_within(boxes[k], p, h2)) expected.push_back(k);
            }
            cols.for_each_within(p, h2, [&](std::size_t k) { seen.push_back(k); });
            ASSERT_EQ(seen, expected) << n << " boxes, p " << str(p) << " h2 " << h2;
            for (std::size_t from = 0; from <= boxes.size(); ++from) {
                const auto it = std::lower_bound(expected.begin(), expected.end(), from);
                const std::size_t want = it == expected.end() ? boxes.size() : *it;
                ASSERT_EQ(cols.first_within(from, p, h2), want) << n << " boxes, from " << from;
            }
        }
    }
}

TEST(BoxColumns, ANaNPointIsNearNoBox) {
    BoxColumns cols;
    for (int k = 0; k < 3; ++k) cols.push({Vec3(-1, -1, -1), Vec3(1, 1, 1)});
    const double nan = std::numeric_limits<double>::quiet_NaN();
    int found = 0;
    cols.for_each_within(Vec3(nan, 0, 0), 100.0, [&](std::size_t) { ++found; });
    EXPECT_EQ(found, 0);
    EXPECT_EQ(cols.first_within(0, Vec3(0, nan, 0), 100.0), 3u);
    EXPECT_EQ(cols.first_within(0, Vec3(0, 0, 0), nan), 3u);
}

// The scan next_touching stands for: every candidate from k on, in order.
std::size_t scan_all(const Candidates& c, std::size_t k, const Vec3& p, double reach) {
    for (; k < c.boxes.size(); ++k) {
        if (c.may_touch(k, p, reach)) return k;
    }
    return c.boxes.size();
}

TEST(Candidates, NextTouchingThroughItsFocusFindsWhatAScanOfEveryBoxFinds) {
    JETRACE_SEEDED_RNG(rng);
    Candidates cand;
    for (std::uint32_t t = 0; t < 400; ++t) {
        cand.triangles.push_back(t);
        cand.boxes.push_back(random_box(rng, 12.0));
    }
    cand.region = Aabb::around(Vec3::Zero(), 15.0);
    std::normal_distribution<double> step(0.0, 0.3);
    std::uniform_real_distribution<double> reach(2.0, 3.0);
    std::uniform_int_distribution<std::size_t> start(0, 399);
    Vec3 p(0, 0, 0);
    std::size_t focuses_kept = 0;
    for (int move = 0; move < 2000; ++move) {
        p += Vec3(step(rng), step(rng), step(rng));
        p = p.cwiseMax(Vec3(-10, -10, -10)).cwiseMin(Vec3(10, 10, 10));
        const double r = reach(rng);
        const std::size_t size_before = cand.focus_size();
        // A whole pass from the first candidate, then from a random one.
        for (std::size_t k = 0; k <= cand.boxes.size();) {
            const std::size_t got = cand.next_touching(k, p, r);
            ASSERT_EQ(got, scan_all(cand, k, p, r)) << "move " << move << " p " << str(p) << " reach " << r;
            if (got == cand.boxes.size()) break;
            k = got + 1;
        }
        const std::size_t k = start(rng);
        ASSERT_EQ(cand.next_touching(k, p, r), scan_all(cand, k, p, r)) << "from " << k;
        if (cand.focus_size() == size_before) ++focuses_kept;
    }
    // The walk both kept focuses and made new ones.
    EXPECT_GT(focuses_kept, 100u);
    EXPECT_LT(focuses_kept, 1990u);
}

TEST(Candidates, AGatherDropsTheFocus) {
    Candidates cand;
    cand.triangles = {0, 1};
    cand.boxes = {{Vec3(0, 0, 0), Vec3(1, 1, 1)}, {Vec3(5, 0, 0), Vec3(6, 1, 1)}};
    EXPECT_EQ(cand.next_touching(0, Vec3(0.5, 2, 0.5), 1.5), 0u);
    cand.clear();
    cand.triangles = {7};
    cand.boxes = {{Vec3(50, 0, 0), Vec3(51, 1, 1)}};
    // The same point: a focus kept from before the gather would name place 0
    // of the old list; this list has nothing near it.
    EXPECT_EQ(cand.next_touching(0, Vec3(0.5, 2, 0.5), 1.5), 1u);
    EXPECT_EQ(cand.next_touching(0, Vec3(50.5, 2, 0.5), 1.5), 0u);
}

}  // namespace
