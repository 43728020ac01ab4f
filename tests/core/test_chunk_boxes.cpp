// The chunk boxes a grid level keeps (ChunkBoxes) spare most of a gather's
// box tests: an answer "none of this chunk's boxes overlaps the query" or
// "all of them overlap it along this axis" must be certain, whatever the
// scale of the level, flat levels, boxes that only touch the query and
// query bounds a rounding step inside a box's included; a level with a box
// that is not finite gets no answers; and the grid's collect_overlapping,
// which drops chunks and tests the rest along the axes those answers
// leave, must keep exactly what the walk that tests every box keeps, in
// the same order, on both of the grid's levels.
//
// Random tests draw from std::mt19937_64 (JETRACE_TEST_SEED replays one;
// see tests/support/test_seed.hpp).
#include "jetrace/core/chunk_boxes.hpp"
#include "jetrace/core/uniform_grid.hpp"

#include "support/random_geometry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

using namespace jetrace;
using namespace jetrace::test;

namespace {

// `n` boxes along a winding strip around `origin` (neighbours near each
// other, as a mesh lists them), each `size` wide or less, some flat along
// an axis; with `flat_y`, all at one height.
std::vector<FloatBox> strip(std::mt19937_64& rng, std::size_t n, const Vec3& origin, double span, double size,
                            bool flat_y = false) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<FloatBox> boxes;
    Vec3 at = origin;
    for (std::size_t i = 0; i < n; ++i) {
        at += random_in_box(rng, Vec3::Constant(-size), Vec3::Constant(size));
        at = at.cwiseMax(origin - Vec3::Constant(span)).cwiseMin(origin + Vec3::Constant(span));
        if (flat_y) at.y() = origin.y();
        Vec3 extent(size * unit(rng), size * unit(rng), size * unit(rng));
        if (flat_y || unit(rng) < 0.2) extent.y() = 0.0;  // a flat triangle's box
        boxes.push_back(FloatBox::around(Aabb{at, at + extent}));
    }
    return boxes;
}

// `v` or its neighbour on either side (the bounds rounding would decide).
double near(std::mt19937_64& rng, double v) {
    const int pick = std::uniform_int_distribution<int>(0, 2)(rng);
    if (pick == 0) return v;
    return std::nextafter(v, pick == 1 ? -std::numeric_limits<double>::infinity()
                                       : std::numeric_limits<double>::infinity());
}

// A query box: random, or with bounds at or a step beside a bound of one of
// the boxes (touching it, just missing it, just inside its extreme).
Aabb query_near(std::mt19937_64& rng, const std::vector<FloatBox>& boxes, const Vec3& origin, double span) {
    std::uniform_int_distribution<std::size_t> pick(0, boxes.size() - 1);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Vec3 c = random_in_box(rng, origin - Vec3::Constant(span), origin + Vec3::Constant(span));
    const Vec3 half = random_in_box(rng, Vec3::Zero(), Vec3::Constant(0.6 * span));
    Aabb q{c - half, c + half};
    for (int i = 0; i < 3; ++i) {
        const double r = unit(rng);
        if (r < 0.2) q.min[i] = near(rng, boxes[pick(rng)].hi[i]);
        if (r >= 0.2 && r < 0.4) q.min[i] = near(rng, boxes[pick(rng)].lo[i]);
        const double s = unit(rng);
        if (s < 0.2) q.max[i] = near(rng, boxes[pick(rng)].lo[i]);
        if (s >= 0.2 && s < 0.4) q.max[i] = near(rng, boxes[pick(rng)].hi[i]);
        if (q.min[i] > q.max[i]) std::swap(q.min[i], q.max[i]);
    }
    return q;
}

// Checks every verdict of `chunks` (over `items` with `boxes`) for `q`
// against each box's own test; the count of chunks with a verdict that
// spares a test (dropped, or an axis untested).
int check_verdicts(const ChunkBoxes& chunks, const std::vector<std::uint32_t>& items,
                   const std::vector<FloatBox>& boxes, const Aabb& q, const std::string& what) {
    const ChunkBoxes::Query cq = chunks.query(q);
    int decided = 0;
    for (std::size_t c = 0; c * ChunkBoxes::kLength < items.size(); ++c) {
        const ChunkBoxes::Verdict v = chunks.classify(c, cq);
        decided += v.none || v.untested != 7 ? 1 : 0;
        const std::size_t end = std::min(items.size(), (c + 1) * ChunkBoxes::kLength);
        for (std::size_t k = c * ChunkBoxes::kLength; k < end; ++k) {
            const FloatBox& b = boxes[items[k]];
            if (v.none) {
                EXPECT_FALSE(b.aabb().overlaps(q)) << what << ", chunk " << c << ", pair " << k << ": dropped";
                continue;
            }
            for (int i = 0; i < 3; ++i) {
                if ((v.untested >> i & 1u) != 0) continue;
                EXPECT_TRUE(b.lo[i] <= q.max[i] && q.min[i] <= b.hi[i])
                    << what << ", chunk " << c << ", pair " << k << ": kept along axis " << i << " untested";
            }
        }
    }
    return decided;
}

}  // namespace

TEST(ChunkBoxes, VerdictsAreCertainAtEveryScale) {
    JETRACE_SEEDED_RNG(rng);
    struct Scale {
        Vec3 origin;
        double span, size;
        bool flat_y;
    };
    // Track scale, far from the world's origin, huge and tiny levels, and a
    // level flat in y.
    const Scale scales[] = {{{0, 0, 0}, 200.0, 3.0, false},
                            {{-9e5, 1e3, 7e5}, 500.0, 2.0, false},
                            {{0, 0, 0}, 9e5, 4e4, false},
                            {{12.5, -3, 8}, 0.01, 0.001, false},
                            {{40, 7.25, -60}, 200.0, 3.0, true}};
    for (const Scale& s : scales) {
        const std::string level = "level around (" + std::to_string(s.origin.x()) + ", " +
                                  std::to_string(s.origin.z()) + "), span " + std::to_string(s.span);
        SCOPED_TRACE(level);
        const std::vector<FloatBox> boxes = strip(rng, 4000, s.origin, s.span, s.size, s.flat_y);
        std::vector<std::uint32_t> items(boxes.size());
        for (std::uint32_t i = 0; i < items.size(); ++i) items[i] = i;
        std::shuffle(items.begin() + 2000, items.end(), rng);  // half in mesh order, half scattered
        ChunkBoxes chunks;
        chunks.build(items, boxes);
        int decided = 0, asked = 0;
        for (int qi = 0; qi < 300 && !::testing::Test::HasFailure(); ++qi) {
            decided += check_verdicts(chunks, items, boxes, query_near(rng, boxes, s.origin, s.span),
                                      "query " + std::to_string(qi));
            asked += static_cast<int>(items.size() / ChunkBoxes::kLength);
        }
        // Most chunks are dropped or need fewer than three axes tested, or the
        // chunks save nothing.
        EXPECT_GT(decided, asked / 3) << "chunks decided " << decided << " of " << asked;
    }
}

// A box with a NaN bound overlaps nothing (Aabb::overlaps): no chunk may be
// kept along that axis without a test. A box over everything overlaps every
// box: every chunk is kept whole.
TEST(ChunkBoxes, NaNIsTestedAndEverythingIsKept) {
    JETRACE_SEEDED_RNG(rng);
    const std::vector<FloatBox> boxes = strip(rng, 70, Vec3::Zero(), 50.0, 2.0);  // a part chunk at the end
    std::vector<std::uint32_t> items(boxes.size());
    for (std::uint32_t i = 0; i < items.size(); ++i) items[i] = i;
    ChunkBoxes chunks;
    chunks.build(items, boxes);
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    const ChunkBoxes::Query with_nan = chunks.query(Aabb{Vec3(nan, 0, 0), Vec3(100, 100, 100)});
    const ChunkBoxes::Query everything = chunks.query(Aabb{Vec3::Constant(-inf), Vec3::Constant(inf)});
    for (std::size_t c = 0; c * ChunkBoxes::kLength < items.size(); ++c) {
        const ChunkBoxes::Verdict v = chunks.classify(c, with_nan);
        EXPECT_TRUE(v.none || (v.untested & 1u) != 0) << "chunk " << c << ": x must be tested";
        EXPECT_FALSE(chunks.classify(c, everything).none) << "chunk " << c;
        EXPECT_EQ(chunks.classify(c, everything).untested, 0u) << "chunk " << c;
    }
}

// The grid does not validate its triangles: a level holding a box that is
// not finite gets no verdicts (the walk then tests every box, as without
// chunks), whatever the other boxes are.
TEST(ChunkBoxes, NoVerdictsForALevelWithABoxThatIsNotFinite) {
    JETRACE_SEEDED_RNG(rng);
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (const double bad : {nan, inf, -inf}) {
        for (const std::size_t at : {std::size_t{0}, std::size_t{15}, std::size_t{40}}) {
            SCOPED_TRACE("a bound " + std::to_string(bad) + " in box " + std::to_string(at));
            std::vector<FloatBox> boxes = strip(rng, 64, Vec3::Zero(), 50.0, 2.0);
            boxes[at].lo[0] = static_cast<float>(bad);
            boxes[at].hi[0] = static_cast<float>(bad);
            std::vector<std::uint32_t> items(boxes.size());
            for (std::uint32_t i = 0; i < items.size(); ++i) items[i] = i;
            ChunkBoxes chunks;
            chunks.build(items, boxes);
            for (int qi = 0; qi < 50; ++qi) {
                const Aabb q = query_near(rng, boxes, Vec3::Zero(), 50.0);
                EXPECT_EQ(check_verdicts(chunks, items, boxes, q, "query " + std::to_string(qi)), 0);
            }
        }
    }
}

TEST(ChunkBoxes, GridCollectsWhatTestingEveryBoxCollects) {
    JETRACE_SEEDED_RNG(rng);
    // Small triangles in mesh order (the fine level), and 300 large ones
    // over 60 m (the coarse level, 40 m cells: more than a chunk a cell).
    std::vector<Triangle> tris;
    for (const FloatBox& b : strip(rng, 3000, Vec3::Zero(), 150.0, 1.5)) {
        tris.push_back(Triangle::make(Vec3(b.lo[0], b.lo[1], b.lo[2]), Vec3(b.hi[0], b.lo[1], b.lo[2]),
                                      Vec3(b.lo[0], b.hi[1], b.hi[2])));
    }
    for (int i = 0; i < 300; ++i) {
        const Vec3 a = random_in_box(rng, Vec3(-30, -5, -30), Vec3(30, 5, 30));
        tris.push_back(Triangle::make(a, a + Vec3(200, 0, 5), a + Vec3(3, 2, 190)));
    }
    Aabb bounds{tris[0].a, tris[0].a};
    for (const Triangle& t : tris) {
        bounds.expand(t.bounds().min);
        bounds.expand(t.bounds().max);
    }
    const UniformGrid grid(tris, bounds, 2.5);
    ASSERT_GE(grid.large_count(), 300u) << "the test needs both levels";
    std::vector<FloatBox> grid_boxes(tris.size());
    for (std::uint32_t t = 0; t < tris.size(); ++t) grid_boxes[t] = grid.box(t);
    std::vector<std::uint32_t> out(5, 0xABCDu);  // scratch with room for a few, and a prefix to keep
    for (int qi = 0; qi < 400; ++qi) {
        const Aabb q = query_near(rng, grid_boxes, Vec3::Zero(), 150.0);
        std::vector<std::uint32_t> expected(3, 0xABCDu);  // for_each_bucketed, then each box tested
        grid.for_each_bucketed(q, [&](std::uint32_t t) {
            if (grid.box(t).aabb().overlaps(q)) expected.push_back(t);
        });
        const std::size_t n = grid.collect_overlapping(q, out, 3);
        ASSERT_EQ(std::vector<std::uint32_t>(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n)), expected)
            << "query " << qi;
    }
}
