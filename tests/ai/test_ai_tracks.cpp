// The driving AI completes laps of `stadium` (wall included), of tracks
// imported from OBJ files, including shapes it was not tuned on, and of a
// real levels loaded through their manifests (docs/tracks/zdm2.track.json,
// docs/tracks/truck_town.track.json, and the OBJ levels fdm6, pandora and
// dutility).
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/ai/road_profile.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

// Runs `cars` AI cars (skill seed `seed`) for up to `seconds`; returns how
// many finished, and adds the cars' respawns to `respawns`.
int finishers(jetrace::Track track, int cars, int laps, double seconds, std::uint64_t seed, int& respawns) {
    const jetrace::Scene scene = jetrace::Scene::make(std::move(track), jetrace::PhysicsSettings{});
    jetrace::WorldState st = jetrace::start_race(scene, cars, laps);
    jetrace::StepScratch scratch;
    jetrace::run_ai(jetrace::Course(scene), st, jetrace::skills_for(cars, seed), static_cast<std::uint32_t>(seconds * 120), true,
                    scratch);
    int n = 0;
    for (const auto& c : st.cars) {
        n += c.finished ? 1 : 0;
        respawns += static_cast<int>(c.respawns);
    }
    return n;
}

int finishers(jetrace::Track track, int cars, int laps, double seconds) {
    int respawns = 0;
    return finishers(std::move(track), cars, laps, seconds, 3, respawns);
}

jetrace::Track truck_town() {
    jetrace::Track t;
    std::string error;
    EXPECT_TRUE(jetrace::load_track(std::string(JETRACE_SOURCE_DIR) + "/docs/tracks/truck_town.track.json", t, error))
        << error;
    return t;
}

jetrace::Track through_obj(const jetrace::Track& t) {
    jetrace::Track out;
    std::string error;
    EXPECT_TRUE(jetrace::import_obj(jetrace::export_obj(t), t.name + "_obj", out, error)) << error;
    return out;
}

}  // namespace

TEST(AiTracks, EveryCarFinishesALapOfStadiumWallIncluded) {
    jetrace::Track t;
    ASSERT_TRUE(jetrace::make_builtin_track("stadium", t));
    EXPECT_EQ(finishers(std::move(t), 4, 1, 240), 4);
}

TEST(AiTracks, EveryCarFinishesImportedRing) {
    jetrace::Track t;
    ASSERT_TRUE(jetrace::make_builtin_track("ring", t));
    EXPECT_EQ(finishers(through_obj(t), 6, 2, 120), 6);
}

TEST(AiTracks, EveryCarFinishesAnImportedTrackOfAnotherShape) {
    // Tight turns, a narrow road and a short wall: not a shape the AI was tuned on.
    jetrace::OvalParams p = jetrace::ring_params();
    p.name = "hairpin";
    p.straight_m = 300;
    p.turn_radius_m = 25;
    p.width_m = 24;
    p.turn_segments = 16;
    p.wall = true;
    p.wall_start_m = 60;
    p.wall_length_m = 150;
    p.wall_curve_radius_m = 25;
    p.finish_line_m = 280;
    p.spawn_slots = 8;
    EXPECT_EQ(finishers(through_obj(jetrace::make_oval(p)), 4, 1, 240), 4);
}

TEST(AiTracks, SevenOfEightFinishALapOfZdm2) {
    // A real level: gates every 15 m along a route with right-angle corners,
    // the start line at one of them (half the grid starts beside its plane).
    jetrace::Track t;
    std::string error;
    ASSERT_TRUE(jetrace::load_track(std::string(JETRACE_SOURCE_DIR) + "/docs/tracks/zdm2.track.json", t, error))
        << error;
    EXPECT_GE(finishers(std::move(t), 8, 1, 120), 7);
}

TEST(AiTracks, EveryCarFinishesALapOfTruckTown) {
    // A real level on hilly terrain: the town's streets, a bridge over a
    // ravine and crests that throw a fast car into the air.
    EXPECT_EQ(finishers(truck_town(), 8, 1, 120), 8);
}

TEST(AiTracks, CarsSlowForTheCrestsOfTruckTown) {
    // A car that takes a crest too fast flies off the road and respawns;
    // the AI slows for the crests it sees in the road's heights ahead.
    int respawns = 0;
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
        EXPECT_EQ(finishers(truck_town(), 8, 1, 120, seed, respawns), 8) << "seed " << seed;
    }
    EXPECT_LE(respawns, 3) << "of 24 cars";
}

TEST(AiTracks, SevenOfEightFinishALapOfEachObjLevel) {
    // Real levels exported as OBJ from Cube 2: Sauerbraten (fdm6, pandora) and
    // Red Eclipse (dutility), routed on one floor each (docs/tracks/), over
    // three skill seeds.
    for (const char* level : {"fdm6", "pandora", "dutility"}) {
        jetrace::Track t;
        std::string error;
        ASSERT_TRUE(jetrace::load_track(std::string(JETRACE_SOURCE_DIR) + "/docs/tracks/" + level + ".track.json", t,
                                        error))
            << level << ": " << error;
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            int respawns = 0;
            EXPECT_GE(finishers(t, 8, 1, 120, seed, respawns), 7) << level << ", skill seed " << seed;
        }
    }
}

TEST(AiTracks, TruckTownWithItsWindingFlippedIsReadAndRacedAlike) {
    // A mesh exported with its winding flipped: every floor faces down and
    // every ceiling up. The physics drives on faces either way; the AI's
    // road profile (its crests) reads the same road, and the cars finish.
    const jetrace::Track t = truck_town();
    jetrace::Track flipped = t;
    flipped.triangles.clear();
    for (const jetrace::Triangle& tri : t.triangles) jetrace::add_triangle(flipped, tri.a, tri.c, tri.b);
    const jetrace::Scene a = jetrace::Scene::make(jetrace::Track(t), jetrace::PhysicsSettings{});
    const jetrace::Scene b = jetrace::Scene::make(jetrace::Track(flipped), jetrace::PhysicsSettings{});
    const jetrace::RoadProfile ra = jetrace::RoadProfile::build(a.track, a.grid);
    const jetrace::RoadProfile rb = jetrace::RoadProfile::build(b.track, b.grid);
    ASSERT_EQ(ra.legs(), rb.legs());
    int road = 0;
    for (std::int32_t leg = 0; leg < static_cast<std::int32_t>(ra.legs()); ++leg) {
        for (int s = 0; s <= 200; ++s) {
            double ya = 0, yb = 0;
            const bool oka = ra.height(leg, s / 200.0, ya), okb = rb.height(leg, s / 200.0, yb);
            ASSERT_EQ(oka, okb) << "leg " << leg << " sample " << s;
            if (!oka) continue;
            ++road;
            EXPECT_NEAR(ya, yb, 2 * jetrace::RoadProfile::kResolution_m) << "leg " << leg << " sample " << s;
        }
    }
    EXPECT_GT(road, 0);
    int respawns = 0;
    EXPECT_EQ(finishers(std::move(flipped), 8, 1, 120, 1, respawns), 8);
    EXPECT_LE(respawns, 3);
}
