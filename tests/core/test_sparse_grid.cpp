// The sparse uniform grid on wide tracks (five stadiums over tens of km, plus
// scattered, long and lattice-snapped triangles): for_each_candidate and
// cell_range against a written-out bucketing, the 10 m cell edge whatever
// the extent, memory that follows the occupied cells, and huge triangles
// growing the edge within the pair budget.
//
// Random tests draw from std::mt19937_64. The seed is fixed by default; set
// the environment variable JETRACE_TEST_SEED (decimal or 0x-hex) to run with
// another one. Every random test prints the seed it used on failure
// (SCOPED_TRACE) and records it as the test property "seed" (visible with
// --gtest_output=xml), so a failure can be replayed with
//   JETRACE_TEST_SEED=<seed> ./test_sparse_grid --gtest_filter=<test>
#include "jetrace/core/geometry.hpp"
#include "jetrace/core/settings.hpp"
#include "jetrace/core/track.hpp"
#include "jetrace/core/uniform_grid.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include "support/random_geometry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace jetrace;
using namespace jetrace::test;

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
// written-out bucketing; any_candidate stops at the first match of that walk.
void sparse_grid_matches_brute_force(const Track& track, const UniformGrid& grid, const Aabb& grid_bounds,
                                     std::mt19937_64& rng, int queries, int min_nonempty) {
    const Bucketing ref{grid_bounds, 1.0 / grid.cell_size_m(), grid.dims()};
    const std::size_t n = track.triangles.size();
    std::vector<CellRange> bucket(n);
    // The grid buckets each triangle by its box rounded outward to floats.
    for (std::size_t t = 0; t < n; ++t) {
        bucket[t] = ref.range(FloatBox::around(track.triangles[t].bounds()).aabb());
        if (grid.box(static_cast<std::uint32_t>(t)).aabb().min != FloatBox::around(track.triangles[t].bounds()).aabb().min) {
            ADD_FAILURE() << "triangle " << t << ": the grid's box is not its bounds rounded outward";
            return;
        }
    }
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
        double h = i % 4 == 0 ? uniform(rng, 0, 60) : (i % 4 == 1 ? 3.5 : kQueryRadius);
        // Huge boxes: more cells than are occupied, so the grid walks its
        // occupied cells instead of the box's range.
        if (i % 50 == 25) h = uniform(rng, 2000, 30000);
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
        // for_each_bucketed reports the same triangles once per cell of the
        // query's range that holds them (the overlap of the two ranges).
        std::vector<std::uint32_t> bucketed;
        grid.for_each_bucketed(box, [&](std::uint32_t t) { bucketed.push_back(t); });
        std::size_t pairs = 0;
        for (const std::uint32_t t : want) {
            std::size_t cells = 1;
            for (int k = 0; k < 3; ++k) {
                cells *= static_cast<std::size_t>(std::min(bucket[t].hi[k], q.hi[k]) - std::max(bucket[t].lo[k], q.lo[k]) + 1);
            }
            pairs += cells;
        }
        std::sort(bucketed.begin(), bucketed.end());
        const std::size_t reports = bucketed.size();
        bucketed.erase(std::unique(bucketed.begin(), bucketed.end()), bucketed.end());
        if (bucketed != want || reports != pairs) {
            ++failures;
            ADD_FAILURE() << "query " << i << ": for_each_bucketed reported " << reports << " ("
                          << bucketed.size() << " triangles), brute force " << want.size() << " in " << pairs
                          << " cells";
        }
        // any_candidate walks the same sequence and stops at the first match.
        const std::uint32_t mod = 2 + static_cast<std::uint32_t>(i % 5);
        const auto match = [&](std::uint32_t t) { return t % mod == 0; };
        const auto first = std::find_if(got.begin(), got.end(), match);
        std::vector<std::uint32_t> walked;
        const bool any = grid.any_candidate(box, [&](std::uint32_t t) {
            walked.push_back(t);
            return match(t);
        });
        const std::vector<std::uint32_t> prefix(got.begin(), first == got.end() ? got.end() : first + 1);
        if (any != (first != got.end()) || walked != prefix) {
            ++failures;
            ADD_FAILURE() << "query " << i << ": any_candidate walked " << walked.size() << " and found " << any
                          << ", for_each_candidate's prefix is " << prefix.size();
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
    // 10 m cells: the lattice the stadiums and the snapped triangles sit on.
    const UniformGrid grid(track.triangles, track.bounds, 2.5, 10.0, UniformGrid::Levels::one);
    ASSERT_EQ(grid.cell_size_m(), 10.0);
    sparse_grid_matches_brute_force(track, grid, track.bounds, rng, 4000, 1400);
    // Bounds smaller than the mesh: buckets and queries clamp to the edge
    // cells, which then hold many triangles; each is still reported once.
    const Aabb shrunk{track.bounds.min + Vec3(2500, 0, 1200), track.bounds.max - Vec3(2500, 600, 1200)};
    const UniformGrid clamped(track.triangles, shrunk, 2.5, 10.0, UniformGrid::Levels::one);
    sparse_grid_matches_brute_force(track, clamped, shrunk, rng, 2000, 300);
    // The rule's edge (the typical triangle: the stadiums' 35 m squares).
    const UniformGrid ruled(track.triangles, track.bounds, 2.5, 0.0, UniformGrid::Levels::one);
    ASSERT_GT(ruled.cell_size_m(), 10.0);
    sparse_grid_matches_brute_force(track, ruled, track.bounds, rng, 2000, 700);
}

TEST(SparseGrid, CellEdgeIgnoresTheExtentAndMemoryFollowsEntries) {
    // Five stadiums over 54 km x 22 km, then the same over 108 km x 44 km:
    // the rule's edge is the same for both (to the rounding of the shifted
    // corners).
    const Track near = wide_sparse_track(nullptr, 1.0);
    const Track far = wide_sparse_track(nullptr, 2.0);
    const double edge = UniformGrid::cell_size_for(near.triangles, near.bounds, 2.5);
    EXPECT_NEAR(UniformGrid::cell_size_for(far.triangles, far.bounds, 2.5), edge, 1e-9 * edge);
    // On the 10 m lattice the stadiums sit on, so that both bucket alike.
    const UniformGrid a(near.triangles, near.bounds, 2.5, 10.0, UniformGrid::Levels::one);
    const UniformGrid b(far.triangles, far.bounds, 2.5, 10.0, UniformGrid::Levels::one);
    for (const UniformGrid* g : {&a, &b}) {
        const double dense_cells = double(g->dims()[0]) * g->dims()[1] * g->dims()[2];
        SCOPED_TRACE("dims " + std::to_string(g->dims()[0]) + "x" + std::to_string(g->dims()[1]) + "x" +
                     std::to_string(g->dims()[2]) + ", " + std::to_string(g->cell_count()) + " occupied cells, " +
                     std::to_string(g->entry_count()) + " entries, " + std::to_string(g->memory_bytes()) + " bytes");
        EXPECT_EQ(g->cell_size_m(), 10.0);
        EXPECT_GT(dense_cells, 5e8);
        EXPECT_LE(g->cell_count(), static_cast<std::int64_t>(g->entry_count()));
        // 4 bytes per pair and 12 per chunk of 16 pairs (its box), at most
        // 28 per occupied cell (4-byte hash slots at load >= 1/4, 12-byte
        // cell record) and 24 per triangle (its box in floats).
        const std::size_t chunks = (g->entry_count() + 15) / 16;
        EXPECT_LE(g->memory_bytes(), 4 * g->entry_count() + 12 * chunks + 28 * std::size_t(g->cell_count()) +
                                         24 * near.triangles.size() + 32);
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
    const UniformGrid g(ground.triangles, ground.bounds, 2.5, 0.0, UniformGrid::Levels::one);
    EXPECT_GT(g.cell_size_m(), 10.0);
    EXPECT_LE(static_cast<std::int64_t>(g.entry_count()), UniformGrid::entry_budget(2));
    std::vector<std::uint32_t> got;
    const Aabb car = Aabb::around(Vec3(123.4, 1, -4567.8), kQueryRadius);
    g.for_each_candidate(car, [&](std::uint32_t t) { got.push_back(t); });
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, (std::vector<std::uint32_t>{0, 1}));
    // Two levels: both triangles in the coarse level, within its budget.
    const UniformGrid two(ground.triangles, ground.bounds, 2.5);
    EXPECT_EQ(two.large_count(), 2u);
    EXPECT_LE(static_cast<std::int64_t>(two.entry_count()), UniformGrid::entry_budget(2));
    got.clear();
    two.for_each_candidate(car, [&](std::uint32_t t) { got.push_back(t); });
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, (std::vector<std::uint32_t>{0, 1}));
}

TEST(SparseGrid, TwoLevelsReportEveryOverlappingTriangleOnce) {
    // The wide sparse track in 10 m cells: the stadiums' floor squares
    // (35 m) and the long snapped triangles cover more than kLargeCells
    // cells and go to the coarse level, the rest stays in the fine one.
    // What the gather needs: every triangle whose box overlaps the query
    // box, each once (the gather keeps those and sorts them).
    JETRACE_SEEDED_RNG(rng);
    const Track track = wide_sparse_track(&rng, 1.0);
    const UniformGrid grid(track.triangles, track.bounds, 2.5, 10.0);
    ASSERT_GT(grid.large_count(), 0u);
    ASSERT_LT(grid.large_count(), track.triangles.size());
    const UniformGrid one(track.triangles, track.bounds, 2.5, 10.0, UniformGrid::Levels::one);
    EXPECT_LT(grid.memory_bytes(), one.memory_bytes());
    std::uniform_int_distribution<std::size_t> pick(0, track.triangles.size() - 1);
    std::uniform_real_distribution<double> jitter(-20.0, 20.0), half(0.5, 30.0);
    int failures = 0, nonempty = 0;
    std::vector<std::uint32_t> got, want;
    for (int i = 0; i < 3000 && failures < 10; ++i) {
        const Triangle& t = track.triangles[pick(rng)];
        const Vec3 c = (t.a + t.b + t.c) / 3.0 + Vec3(jitter(rng), jitter(rng) * 0.1, jitter(rng));
        const Aabb box = Aabb::around(c, i % 100 == 0 ? 5000.0 : half(rng));
        got.clear();
        want.clear();
        grid.for_each_candidate(box, [&](std::uint32_t k) { got.push_back(k); });
        for (std::size_t k = 0; k < track.triangles.size(); ++k) {
            if (track.triangles[k].bounds().overlaps(box)) want.push_back(static_cast<std::uint32_t>(k));
        }
        std::sort(got.begin(), got.end());
        const bool unique = std::adjacent_find(got.begin(), got.end()) == got.end();
        const bool covers = std::includes(got.begin(), got.end(), want.begin(), want.end());
        // for_each_bucketed (the walk collect_overlapping filters): the same
        // triangles, repeats allowed.
        std::vector<std::uint32_t> bucketed;
        grid.for_each_bucketed(box, [&](std::uint32_t k) { bucketed.push_back(k); });
        std::sort(bucketed.begin(), bucketed.end());
        bucketed.erase(std::unique(bucketed.begin(), bucketed.end()), bucketed.end());
        nonempty += want.empty() ? 0 : 1;
        if (!unique || !covers || bucketed != got) {
            ++failures;
            ADD_FAILURE() << "query " << i << " box " << str(box.min) << str(box.max) << ": grid reported "
                          << got.size() << (unique ? "" : " with duplicates") << ", " << want.size()
                          << " overlap it" << (covers ? "" : ", not all reported") << "; for_each_bucketed "
                          << bucketed.size() << " distinct";
        }
    }
    EXPECT_EQ(failures, 0);
    EXPECT_GE(nonempty, 1500);
}
