// The road profile the driving AI reads crests from: heights along the route
// against the road's own geometry (a tilted plane, a hole, a deck above a
// floor), and the leg numbering the AI indexes it with.
#include "jetrace/ai/road_profile.hpp"
#include "jetrace/core/world.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <utility>
#include <vector>

namespace {

using jetrace::Checkpoint;
using jetrace::Pose;
using jetrace::RoadProfile;
using jetrace::Scene;
using jetrace::Vec3;

// A square route of four gates, 200 m a side, at height `y(x)` + 1 m.
std::vector<Checkpoint> square_route(double slope) {
    const Vec3 corners[4] = {Vec3(100, 0, -100), Vec3(100, 0, 100), Vec3(-100, 0, 100), Vec3(-100, 0, -100)};
    std::vector<Checkpoint> gates;
    for (int k = 0; k < 4; ++k) {
        Checkpoint g;
        g.center = corners[k] + Vec3(0, slope * corners[k].x() + 1.0, 0);
        g.respawn = Pose{g.center, Vec3(1, 0, 0), Vec3(0, 1, 0)};
        gates.push_back(g);
    }
    return gates;
}

// A quad from (x0, z0) to (x1, z1) on the plane y = slope x + lift, facing up.
void add_quad(std::vector<Vec3>& v, std::vector<std::uint32_t>& idx, double x0, double z0, double x1, double z1,
              double slope, double lift) {
    const auto base = static_cast<std::uint32_t>(v.size());
    for (const auto& [x, z] : {std::pair{x0, z0}, {x0, z1}, {x1, z1}, {x1, z0}}) v.emplace_back(x, slope * x + lift, z);
    for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) idx.push_back(base + i);
}

// 10 m quads over x and z from -150 to 150 on the plane y = slope x (small
// quads, so that samples fall on many triangles), but for the `holes`: (i,
// j) is the quad from (10 i, 10 j).
void add_tiles(std::vector<Vec3>& v, std::vector<std::uint32_t>& idx, double slope,
               std::initializer_list<std::pair<int, int>> holes = {}) {
    for (int i = -15; i < 15; ++i) {
        for (int j = -15; j < 15; ++j) {
            if (std::find(holes.begin(), holes.end(), std::pair{i, j}) != holes.end()) continue;
            add_quad(v, idx, i * 10.0, j * 10.0, i * 10.0 + 10, j * 10.0 + 10, slope, 0);
        }
    }
}

Scene scene_of(const std::vector<Vec3>& v, const std::vector<std::uint32_t>& idx, std::vector<Checkpoint> gates) {
    const Pose spawn = gates.front().respawn;
    return Scene::make(jetrace::make_track("profile", v, idx, std::move(gates), {spawn}, -1000),
                       jetrace::PhysicsSettings{});
}

// The point a fraction t along the leg into gate `leg`.
RoadProfile road_of(const Scene& sc) { return RoadProfile::build(sc.track, sc.grid); }

Vec3 on_leg(const Scene& sc, int leg, double t) {
    const auto& g = sc.track.checkpoints;
    const int n = static_cast<int>(g.size());
    const Vec3 a = g[static_cast<std::size_t>((leg - 1 + n) % n)].center;
    const Vec3 b = g[static_cast<std::size_t>(leg % n)].center;
    return a + (b - a) * t;
}

}  // namespace

TEST(RoadProfile, FollowsATiltedPlaneAlongEveryLeg) {
    constexpr double kSlope = 0.3;
    std::vector<Vec3> v;
    std::vector<std::uint32_t> idx;
    add_tiles(v, idx, kSlope);
    const Scene sc = scene_of(v, idx, square_route(kSlope));
    const RoadProfile road = road_of(sc);
    ASSERT_EQ(road.legs(), 4u);
    for (int leg = 0; leg < 4; ++leg) {
        for (int s = 0; s <= 100; ++s) {
            const double t = s / 100.0 + (s % 7) * 1e-3;
            const Vec3 p = on_leg(sc, leg, std::min(t, 1.0));
            double y = 0.0;
            ASSERT_TRUE(road.height(leg, t, y)) << "leg " << leg << " t " << t;
            EXPECT_NEAR(y, kSlope * p.x(), jetrace::RoadProfile::kResolution_m) << "leg " << leg << " t " << t;
        }
    }
    // Legs are numbered modulo the gate count, as the AI counts gates ahead.
    double y0 = 0.0, y1 = 0.0, y2 = 0.0;
    ASSERT_TRUE(road.height(1, 0.25, y0));
    ASSERT_TRUE(road.height(5, 0.25, y1));
    ASSERT_TRUE(road.height(-3, 0.25, y2));
    EXPECT_EQ(y0, y1);
    EXPECT_EQ(y0, y2);
}

TEST(RoadProfile, HasNoRoadOverAHole) {
    std::vector<Vec3> v;
    std::vector<std::uint32_t> idx;
    // The floor, with a hole 40 m long across the leg into gate 1 (x = 100,
    // z from -20 to 20).
    add_quad(v, idx, -150, -150, 150, -20, 0, 0);
    add_quad(v, idx, -150, 20, 150, 150, 0, 0);
    add_quad(v, idx, -150, -20, 80, 20, 0, 0);
    add_quad(v, idx, 120, -20, 150, 20, 0, 0);
    const Scene sc = scene_of(v, idx, square_route(0));
    double y = 0.0;
    EXPECT_FALSE(road_of(sc).height(1, 0.5, y));     // z = 0: over the hole
    EXPECT_FALSE(road_of(sc).height(1, 0.42, y));    // z = -16
    EXPECT_TRUE(road_of(sc).height(1, 0.3, y));      // z = -40
    EXPECT_EQ(y, 0.0);
    EXPECT_TRUE(road_of(sc).height(2, 0.5, y));      // another leg
}

TEST(RoadProfile, ReadsTheRoadNearestBelowTheRouteNotADeckAboveOrAFloorFarBelow) {
    std::vector<Vec3> v;
    std::vector<std::uint32_t> idx;
    add_quad(v, idx, -150, -150, 150, 150, 0, 0);  // the floor, y = 0
    add_quad(v, idx, 80, -110, 120, 110, 0, 10);   // a deck along leg 1, y = 10
    std::vector<Checkpoint> gates = square_route(0);
    // Under the deck (route at y = 1, the deck 9 m above): the floor.
    const Scene under = scene_of(v, idx, gates);
    double y = -1.0;
    ASSERT_TRUE(road_of(under).height(1, 0.5, y));
    EXPECT_EQ(y, 0.0);
    // On the deck (the route lifted to y = 11 at gates 0 and 1): the deck,
    // though the floor is below it within the probe.
    gates[0].center.y() = 11;
    gates[1].center.y() = 11;
    const Scene over = scene_of(v, idx, gates);
    ASSERT_TRUE(road_of(over).height(1, 0.5, y));
    EXPECT_EQ(y, 10.0);
    // Far above every road: none.
    gates[0].center.y() = 60;
    gates[1].center.y() = 60;
    const Scene high = scene_of(v, idx, gates);
    EXPECT_FALSE(road_of(high).height(1, 0.5, y));
}

// Faces wound either way are road (the physics drives on them alike): a
// floor whose faces point down, under a ceiling whose faces point up 3 m
// above the route line (a mesh exported with its winding flipped), reads
// as the floor, the same heights as the floor wound upwards.
TEST(RoadProfile, ReadsTheFloorWhicheverWayItsFacesAreWoundNotTheCeilingAboveIt) {
    constexpr double kSlope = 0.2;
    auto build = [&](bool flip) {
        std::vector<Vec3> v;
        std::vector<std::uint32_t> idx;
        add_quad(v, idx, -150, -150, 150, 150, kSlope, 0);  // the floor
        add_quad(v, idx, -150, -150, 150, 150, kSlope, 4);  // the ceiling, 4 m above it
        if (flip) {
            for (std::size_t i = 0; i + 2 < idx.size(); i += 3) std::swap(idx[i + 1], idx[i + 2]);
        }
        return scene_of(v, idx, square_route(kSlope));
    };
    const Scene up = build(false), flipped = build(true);
    ASSERT_LT(flipped.track.triangles[0].normal().y(), 0.0);
    const RoadProfile a = road_of(up), b = road_of(flipped);
    for (int leg = 0; leg < 4; ++leg) {
        for (int s = 0; s <= 50; ++s) {
            const double t = s / 50.0;
            const Vec3 p = on_leg(flipped, leg, t);
            double ya = -1.0, yb = -1.0;
            ASSERT_TRUE(a.height(leg, t, ya)) << "leg " << leg << " t " << t;
            ASSERT_TRUE(b.height(leg, t, yb)) << "leg " << leg << " t " << t;
            EXPECT_NEAR(yb, kSlope * p.x(), jetrace::RoadProfile::kResolution_m) << "leg " << leg << " t " << t;
            EXPECT_EQ(ya, yb) << "leg " << leg << " t " << t;
        }
    }
}

// A step up of more than 1.25 m along a leg is not the road driven on (it
// is a block's top, or a deck overhead): the road goes on at the floor,
// and the block is marked as an obstacle on the route.
TEST(RoadProfile, GoesOnAtTheFloorUnderABlockTopHigherThanAStep) {
    std::vector<Vec3> v;
    std::vector<std::uint32_t> idx;
    add_quad(v, idx, -150, -150, 150, 150, 0, 0);  // the floor, y = 0
    add_quad(v, idx, 90, -10, 110, 10, 0, 2);      // a block's top across leg 1 (x = 100), 2 m up
    add_quad(v, idx, 90, 40, 110, 60, 0, 1);       // a 1 m step further along it
    const Scene sc = scene_of(v, idx, square_route(0));
    const RoadProfile road = road_of(sc);
    double y = -1.0;
    ASSERT_TRUE(road.height(1, 0.5, y));   // z = 0: on the floor under the block's top
    EXPECT_EQ(y, 0.0);
    EXPECT_TRUE(road.obstacle(1, 0.5));    // and the block is marked
    EXPECT_FALSE(road.obstacle(1, 0.25));  // z = -50: the floor only
    EXPECT_FALSE(road.obstacle(1, 0.75));  // the step is road, not an obstacle
    ASSERT_TRUE(road.height(1, 0.75, y));  // z = 50: up the step
    EXPECT_EQ(y, 1.0);
}

TEST(RoadProfile, GivesALevelLegsOneHeightAndNaNForTheRest) {
    constexpr double kSlope = 0.3;
    std::vector<Vec3> v;
    std::vector<std::uint32_t> idx;
    add_tiles(v, idx, kSlope);
    // Legs 1 and 3 run along z at one x: level, the road 1 m below the
    // route line. Legs 0 and 2 climb and fall along x.
    const Scene sc = scene_of(v, idx, square_route(kSlope));
    const RoadProfile road = road_of(sc);
    for (int leg : {0, 2}) EXPECT_TRUE(std::isnan(road.level_height(leg))) << "leg " << leg;
    for (int leg : {1, 3}) {
        const double y = road.level_height(leg);
        ASSERT_FALSE(std::isnan(y)) << "leg " << leg;
        EXPECT_NEAR(y, kSlope * on_leg(sc, leg, 0.5).x(), RoadProfile::kResolution_m);
        EXPECT_EQ(road.level_height(leg + 4), y);
        EXPECT_EQ(road.level_height(leg - 8), y);
        for (int s = 0; s <= 1000; ++s) {
            const RoadProfile::Sample here = road.sample(leg, s / 1000.0);
            ASSERT_TRUE(here.has_height);
            EXPECT_FALSE(here.obstacle);
            EXPECT_EQ(here.y, y) << "leg " << leg << " t " << s / 1000.0;
        }
    }
    EXPECT_NE(road.level_height(1), road.level_height(3));
}

TEST(RoadProfile, HasNoLevelHeightWhereALegCrossesAHoleOrAnObstacle) {
    std::vector<Vec3> v;
    std::vector<std::uint32_t> idx;
    // A flat floor with a hole under the middle of leg 1 (x = 100, z near
    // 0) and a block 3 m high on leg 3 (x = -100).
    add_tiles(v, idx, 0.0, {{9, 0}, {10, 0}});
    add_quad(v, idx, -105, -5, -95, 5, 0.0, 3.0);
    const Scene sc = scene_of(v, idx, square_route(0.0));
    const RoadProfile road = road_of(sc);
    EXPECT_FALSE(std::isnan(road.level_height(0)));
    EXPECT_FALSE(std::isnan(road.level_height(2)));
    EXPECT_TRUE(std::isnan(road.level_height(1)));
    EXPECT_TRUE(std::isnan(road.level_height(3)));
    EXPECT_EQ(road.level_height(0), road.level_height(2));
}
