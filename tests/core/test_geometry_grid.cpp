// The uniform grid against brute force (the stadium and a random mesh with
// degenerate, flat and lattice-snapped triangles, at several cell sizes), the
// documented cell-size rule, and the seed's regression: inclined, flat and
// vertical planes, also on cell boundaries, must be found.
//
// Random tests draw from std::mt19937_64. The seed is fixed by default; set
// the environment variable JETRACE_TEST_SEED (decimal or 0x-hex) to run with
// another one. Every random test prints the seed it used on failure
// (SCOPED_TRACE) and records it as the test property "seed" (visible with
// --gtest_output=xml), so a failure can be replayed with
//   JETRACE_TEST_SEED=<seed> ./test_geometry_grid --gtest_filter=<test>
#include "jetrace/core/geometry.hpp"
#include "jetrace/core/resolver.hpp"
#include "jetrace/core/settings.hpp"
#include "jetrace/core/track.hpp"
#include "jetrace/core/uniform_grid.hpp"
#include "jetrace/core/world.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include "support/random_geometry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <vector>

using namespace jetrace;
using namespace jetrace::test;

// =========================================================== grid vs brute

namespace {

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
        gather_candidates({track, grid, Broadphase::grid, PhysicsSettings{}}, c, kQueryRadius, cand);
        if (!std::is_sorted(cand.triangles.begin(), cand.triangles.end()) ||
            std::adjacent_find(cand.triangles.begin(), cand.triangles.end()) != cand.triangles.end() ||
            !std::includes(cand.triangles.begin(), cand.triangles.end(), brute[qi].begin(), brute[qi].end())) {
            ++failures;
            ADD_FAILURE() << "gather_candidates at " << str(c) << " is unsorted, has duplicates or misses a triangle";
        }
        // ... and keeps exactly the triangles whose grid boxes (their bounds
        // rounded outward to floats) reach the gathered region, each with
        // that box, which contains the triangle.
        std::vector<std::uint32_t> overlapping;
        const Vec3 slack(kBoxSlack_m, kBoxSlack_m, kBoxSlack_m);
        const Aabb region{cand.region.min - slack, cand.region.max + slack};
        for (std::uint32_t t = 0; t < track.triangles.size(); ++t) {
            if (grid.box(t).aabb().overlaps(region)) overlapping.push_back(t);
        }
        bool boxes_hold = cand.boxes.size() == cand.triangles.size();
        for (std::size_t k = 0; boxes_hold && k < cand.triangles.size(); ++k) {
            const Aabb b = cand.boxes.box(k).aabb();
            const Aabb exact = track.triangles[cand.triangles[k]].bounds();
            boxes_hold = b.min == grid.box(cand.triangles[k]).aabb().min && b.max == grid.box(cand.triangles[k]).aabb().max &&
                         (b.min.array() <= exact.min.array()).all() && (b.max.array() >= exact.max.array()).all();
        }
        if (cand.triangles != overlapping || !boxes_hold) {
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
    // 0 = the documented default rule (the median triangle, 35 m). A 3 m grid over the
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
    // The documented rule: the edge is the median triangle's largest box
    // extent, clamped between 4 and 16 car radii, whatever the track's
    // extent; only the key (at most 2^21 cells per axis) can grow it.
    const Track stadium = make_oval(stadium_params());
    const double typical = UniformGrid::typical_extent_m(stadium.triangles);
    EXPECT_GT(typical, 10.0);  // its floor squares are 35 m wide
    EXPECT_LT(typical, 40.0);
    EXPECT_EQ(UniformGrid::cell_size_for(stadium.triangles, stadium.bounds, 2.5), typical);
    const UniformGrid g(stadium.triangles, stadium.bounds, 2.5);
    EXPECT_EQ(g.cell_size_m(), typical);
    // cell_count() counts occupied cells only.
    EXPECT_GT(g.cell_count(), 0);
    EXPECT_LE(g.cell_count(), static_cast<std::int64_t>(g.entry_count()));
    // The clamp: 4 radii for small triangles (or none), 16 for huge ones.
    EXPECT_EQ(UniformGrid::cell_size_for({}, stadium.bounds, 2.5), 10.0);
    EXPECT_EQ(UniformGrid::cell_size_for(stadium.triangles, stadium.bounds, 1.0), 16.0);
    EXPECT_EQ(UniformGrid::cell_size_for(stadium.triangles, stadium.bounds, 20.0), 80.0);
    // A 200 km box, and the largest box a track may span (2,000 km), keep 10 m cells.
    const Aabb huge{Vec3(-1e5, -1e3, -1e5), Vec3(1e5, 1e3, 1e5)};
    EXPECT_EQ(UniformGrid::cell_size_for({}, huge, 2.5), 10.0);
    const double m = kMaxTrackCoordinate_m;
    const Aabb largest{Vec3(-m, -m, -m), Vec3(m, m, m)};
    EXPECT_EQ(UniformGrid::cell_size_for({}, largest, 2.5), 10.0);
    // A radius too small for the key: the edge grows by factors of 1.0625
    // until every axis fits, and stops at the first that does.
    const double grown = UniformGrid::cell_size_for({}, largest, 1e-4);
    EXPECT_LE(std::floor(2 * m * (1.0 / grown)) + 1, UniformGrid::kMaxAxisCells);
    EXPECT_LE(grown, 1.0625 * 2 * m / (UniformGrid::kMaxAxisCells - 1) * (1 + 1e-9));
    // An explicit size is kept when the key allows it.
    EXPECT_EQ(UniformGrid(stadium.triangles, stadium.bounds, 2.5, 3.0).cell_size_m(), 3.0);
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
            const TrackQuery q{plane.track, grid, bp, ps};
            gather_candidates(q, c, r + ps.contact_skin_m + 0.5, cand);
            find_contacts(q, cand, c, contacts);
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
    // floor lies exactly on a cell boundary of the 10 m grid.
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
