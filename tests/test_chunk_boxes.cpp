// The chunk boxes a grid level keeps (ChunkBoxes) decide most of a gather's
// pairs with fewer tests of their boxes: an answer "none of this chunk's
// boxes overlaps the query" or "all of them overlap it along this axis"
// must be certain, whatever the scale of the level, boxes that only touch
// the query included; and the grid's collect_overlapping, which drops
// chunks and tests the rest along the axes left by those answers, must
// keep exactly the pairs whose own boxes overlap.
//
// Random tests draw from std::mt19937_64 (JETRACE_TEST_SEED replays one;
// see tests/support/test_seed.hpp).
#include "jetrace/chunk_boxes.hpp"
#include "jetrace/uniform_grid.hpp"

#include "support/random_geometry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <cstdint>
#include <random>
#include <vector>

using namespace jetrace;
using namespace jetrace::test;

namespace {

// `n` boxes along a winding strip around `origin` (neighbours near each
// other, as a mesh lists them), each `size` wide or less, some flat along
// an axis.
std::vector<FloatBox> strip(std::mt19937_64& rng, std::size_t n, const Vec3& origin, double span, double size) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<FloatBox> boxes;
    Vec3 at = origin;
    for (std::size_t i = 0; i < n; ++i) {
        at += random_in_box(rng, Vec3::Constant(-size), Vec3::Constant(size));
        at = at.cwiseMax(origin - Vec3::Constant(span)).cwiseMin(origin + Vec3::Constant(span));
        Vec3 extent(size * unit(rng), size * unit(rng), size * unit(rng));
        if (unit(rng) < 0.2) extent.y() = 0.0;  // a flat triangle's box
        boxes.push_back(FloatBox::around(Aabb{at, at + extent}));
    }
    return boxes;
}

// A query box: random, or with a bound set exactly to a bound of one of the
// boxes (touching it), the cases where rounding would decide.
Aabb query_near(std::mt19937_64& rng, const std::vector<FloatBox>& boxes, const Vec3& origin, double span) {
    std::uniform_int_distribution<std::size_t> pick(0, boxes.size() - 1);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Vec3 c = random_in_box(rng, origin - Vec3::Constant(span), origin + Vec3::Constant(span));
    const Vec3 half = random_in_box(rng, Vec3::Zero(), Vec3::Constant(0.6 * span));
    Aabb q{c - half, c + half};
    for (int i = 0; i < 3; ++i) {
        if (unit(rng) < 0.3) q.min[i] = boxes[pick(rng)].hi[i];
        if (unit(rng) < 0.3) q.max[i] = boxes[pick(rng)].lo[i];
        if (q.min[i] > q.max[i]) std::swap(q.min[i], q.max[i]);
    }
    return q;
}

}  // namespace

TEST(ChunkBoxes, VerdictsAreCertainAtEveryScale) {
    JETRACE_SEEDED_RNG(rng);
    struct Scale {
        Vec3 origin;
        double span, size;
    };
    // Track scale, far from the world's origin, huge and tiny levels.
    const Scale scales[] = {{{0, 0, 0}, 200.0, 3.0},
                            {{-9e5, 1e3, 7e5}, 500.0, 2.0},
                            {{0, 0, 0}, 9e5, 4e4},
                            {{12.5, -3, 8}, 0.01, 0.001}};
    for (const Scale& s : scales) {
        SCOPED_TRACE("level around (" + std::to_string(s.origin.x()) + ", " + std::to_string(s.origin.z()) +
                     "), span " + std::to_string(s.span));
        const std::vector<FloatBox> boxes = strip(rng, 4000, s.origin, s.span, s.size);
        std::vector<std::uint32_t> items(boxes.size());
        for (std::uint32_t i = 0; i < items.size(); ++i) items[i] = i;
        std::shuffle(items.begin() + 2000, items.end(), rng);  // half in mesh order, half scattered
        ChunkBoxes chunks;
        chunks.build(items, boxes);
        int decided = 0, asked = 0;
        for (int qi = 0; qi < 300; ++qi) {
            const Aabb q = query_near(rng, boxes, s.origin, s.span);
            const ChunkBoxes::Query cq = chunks.query(q);
            for (std::size_t c = 0; c * ChunkBoxes::kLength < items.size(); ++c) {
                const ChunkBoxes::Verdict v = chunks.classify(c, cq);
                ++asked;
                decided += v.none || v.crossed != 7 ? 1 : 0;
                const std::size_t end = std::min(items.size(), (c + 1) * ChunkBoxes::kLength);
                for (std::size_t k = c * ChunkBoxes::kLength; k < end; ++k) {
                    const FloatBox& b = boxes[items[k]];
                    const bool overlaps = b.aabb().overlaps(q);
                    if (v.none) {
                        ASSERT_FALSE(overlaps) << "query " << qi << ", chunk " << c << ", pair " << k
                                               << ": the chunk says none overlaps";
                        continue;
                    }
                    for (int i = 0; i < 3; ++i) {
                        if ((v.crossed >> i & 1u) != 0) continue;
                        ASSERT_TRUE(b.lo[i] <= q.max[i] && b.hi[i] >= q.min[i])
                            << "query " << qi << ", chunk " << c << ", pair " << k << ": the chunk says every box "
                            << "overlaps along axis " << i;
                    }
                }
            }
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
    const std::vector<FloatBox> boxes = strip(rng, 64, Vec3::Zero(), 50.0, 2.0);
    std::vector<std::uint32_t> items(boxes.size());
    for (std::uint32_t i = 0; i < items.size(); ++i) items[i] = i;
    ChunkBoxes chunks;
    chunks.build(items, boxes);
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    const ChunkBoxes::Query with_nan = chunks.query(Aabb{Vec3(nan, 0, 0), Vec3(100, 100, 100)});
    const ChunkBoxes::Query everything = chunks.query(Aabb{Vec3::Constant(-inf), Vec3::Constant(inf)});
    for (std::size_t c = 0; c < items.size() / ChunkBoxes::kLength; ++c) {
        const ChunkBoxes::Verdict v = chunks.classify(c, with_nan);
        EXPECT_TRUE(v.none || (v.crossed & 1u) != 0) << "chunk " << c << ": x must be tested";
        EXPECT_FALSE(chunks.classify(c, everything).none) << "chunk " << c;
        EXPECT_EQ(chunks.classify(c, everything).crossed, 0u) << "chunk " << c;
    }
}

TEST(ChunkBoxes, GridCollectsExactlyTheOverlappingPairs) {
    JETRACE_SEEDED_RNG(rng);
    // Small triangles in mesh order and a few large ones (the coarse level).
    std::vector<Triangle> tris;
    const std::vector<FloatBox> seeds = strip(rng, 3000, Vec3::Zero(), 150.0, 1.5);
    for (const FloatBox& b : seeds) {
        tris.push_back(Triangle::make(Vec3(b.lo[0], b.lo[1], b.lo[2]), Vec3(b.hi[0], b.lo[1], b.lo[2]),
                                      Vec3(b.lo[0], b.hi[1], b.hi[2])));
    }
    for (int i = 0; i < 20; ++i) {
        const Vec3 a = random_in_box(rng, Vec3::Constant(-150), Vec3::Constant(150));
        tris.push_back(Triangle::make(a, a + Vec3(120, 0, 5), a + Vec3(3, 2, 110)));
    }
    Aabb bounds = tris[0].bounds();
    for (const Triangle& t : tris) {
        bounds.expand(t.bounds().min);
        bounds.expand(t.bounds().max);
    }
    const UniformGrid grid(tris, bounds, 2.5);
    ASSERT_GT(grid.large_count(), 0u) << "the test needs both levels";
    std::vector<std::uint32_t> out;
    for (int qi = 0; qi < 400; ++qi) {
        std::vector<FloatBox> grid_boxes(tris.size());
        for (std::uint32_t t = 0; t < tris.size(); ++t) grid_boxes[t] = grid.box(t);
        const Aabb q = query_near(rng, grid_boxes, Vec3::Zero(), 150.0);
        std::vector<std::uint32_t> walked;  // for_each_bucketed, then each box tested
        grid.for_each_bucketed(q, [&](std::uint32_t t) {
            if (grid.box(t).aabb().overlaps(q)) walked.push_back(t);
        });
        const std::size_t n = grid.collect_overlapping(q, out, 0);
        const std::vector<std::uint32_t> got(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n));
        ASSERT_EQ(got, walked) << "query " << qi;
    }
}
