// The drivability warnings of jetrace-track inspect (check_drivability):
// each made-up track triggers its warning, and clean tracks (a flat loop,
// the built-in ring and stadium with its 85 degree wall, the two real
// levels) trigger no gate_unreachable.
#include "jetrace/tracks/builtin_tracks.hpp"
#include "jetrace/tracks/drivability.hpp"
#include "jetrace/tracks/track_io.hpp"
#include "support/made_up_track.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace {

using jetrace::Checkpoint;
using jetrace::DrivabilityWarning;
using jetrace::Pose;
using jetrace::Track;
using jetrace::Vec3;

using jetrace::test::diamond;
using jetrace::test::flat_floor;
using jetrace::test::flat_spawn;
using jetrace::test::gate;
using jetrace::test::kRest_m;
using jetrace::test::Mesh;
using jetrace::test::track_of;

std::string all(const std::vector<DrivabilityWarning>& ws) {
    std::string s;
    for (const auto& w : ws) s += w.kind + " " + w.subject + " " + std::to_string(w.index) + ": " + w.message + "\n";
    return s;
}

const DrivabilityWarning* find(const std::vector<DrivabilityWarning>& ws, const char* kind, std::int64_t index) {
    for (const auto& w : ws) {
        if (w.kind == kind && w.index == index) return &w;
    }
    return nullptr;
}

bool has_kind(const std::vector<DrivabilityWarning>& ws, const char* kind) {
    for (const auto& w : ws) {
        if (w.kind == kind) return true;
    }
    return false;
}

}  // namespace

TEST(Drivability, AFlatLoopWithGatesOnItIsClean) {
    const auto ws = jetrace::check_drivability(track_of(flat_floor(), diamond()));
    EXPECT_TRUE(ws.empty()) << all(ws);
}

TEST(Drivability, TheBuiltInTracksAreClean) {
    for (const char* name : {"ring", "stadium"}) {
        Track t;
        ASSERT_TRUE(jetrace::make_builtin_track(name, t));
        const auto ws = jetrace::check_drivability(t);
        EXPECT_TRUE(ws.empty()) << name << ":\n" << all(ws);
    }
}

TEST(Drivability, TheRealLevelsHaveNoUnreachableGate) {
    for (const char* manifest : {"truck_town.track.json", "zdm2.track.json"}) {
        Track t;
        std::string error;
        ASSERT_TRUE(jetrace::load_track(std::string(JETRACE_SOURCE_DIR) + "/docs/tracks/" + manifest, t, error)) << error;
        const auto ws = jetrace::check_drivability(t);
        for (const char* kind : {jetrace::kGateUnreachable, jetrace::kGateOnObstacle, jetrace::kGateAboveRoad,
                                 jetrace::kFacesPointDown, jetrace::kHeightRange}) {
            EXPECT_FALSE(has_kind(ws, kind)) << manifest << ":\n" << all(ws);
        }
    }
}

TEST(Drivability, AWallAcrossALegMakesItsGateUnreachable) {
    Mesh m = flat_floor();
    m.block(30, 30, 8, 0, 8);  // vertical sides, 8 m tall, on the leg from gate 0 to gate 1
    const auto ws = jetrace::check_drivability(track_of(m, diamond()));
    const DrivabilityWarning* w = find(ws, jetrace::kGateUnreachable, 1);
    ASSERT_NE(w, nullptr) << all(ws);
    EXPECT_EQ(w->subject, "gate");
    EXPECT_EQ(w->position, diamond()[1].center);
    // The floor goes on under the block: the probes see a roof, the ray a wall.
    EXPECT_NE(w->message.find("over a continuous surface: a wall (90 degrees) at"), std::string::npos) << w->message;
    EXPECT_EQ(ws.size(), 1u) << all(ws);
}

TEST(Drivability, AStepUpOntoAPlateauMakesItsGateUnreachable) {
    Mesh m;
    m.floor(-100, -100, 100, 30, 0);
    m.floor(-100, 30, 100, 100, 8);  // 8 m higher beyond z = 30, no face between
    auto gates = diamond();
    gates[1] = gate(0, 60, -1, -1, 8);
    const auto ws = jetrace::check_drivability(track_of(m, gates));
    const DrivabilityWarning* w = find(ws, jetrace::kGateUnreachable, 1);
    ASSERT_NE(w, nullptr) << all(ws);
    EXPECT_NE(w->message.find("a step up of 8.0 m at"), std::string::npos) << w->message;
    // Down from the plateau is a drop: gate 2 is reached.
    EXPECT_EQ(find(ws, jetrace::kGateUnreachable, 2), nullptr) << all(ws);
}

TEST(Drivability, ASharpCreaseIntoASteepFaceIsAWallAndAGentleRampIsNot) {
    Mesh steep = flat_floor();
    steep.block(30, 30, 8, 1.4, 8);  // sides at 80 degrees (76 along the diagonal leg): the probes land on them
    const auto ws = jetrace::check_drivability(track_of(steep, diamond()));
    const DrivabilityWarning* w = find(ws, jetrace::kGateUnreachable, 1);
    ASSERT_NE(w, nullptr) << all(ws);
    EXPECT_NE(w->message.find("a crease of 76 degrees into a face rising at 76 degrees"), std::string::npos)
        << w->message;
    Mesh ramp = flat_floor();
    ramp.block(30, 30, 8, 10, 4);  // sides at 22 degrees
    const auto gentle = jetrace::check_drivability(track_of(ramp, diamond()));
    EXPECT_TRUE(gentle.empty()) << all(gentle);
}

TEST(Drivability, AHoleLongerThanAJumpMakesItsGateUnreachable) {
    Mesh m;
    m.floor(-100, -100, 100, 10, 0);
    m.floor(-100, 40, 100, 100, 0);  // nothing for 30 m across the legs into gates 1 and 2
    const auto ws = jetrace::check_drivability(track_of(m, diamond()));
    const DrivabilityWarning* w = find(ws, jetrace::kGateUnreachable, 1);
    ASSERT_NE(w, nullptr) << all(ws);
    EXPECT_NE(w->message.find("no surface under it from"), std::string::npos) << w->message;
    EXPECT_NE(find(ws, jetrace::kGateUnreachable, 2), nullptr) << all(ws);  // back across it
    EXPECT_EQ(ws.size(), 2u) << all(ws);
    Mesh narrow;
    narrow.floor(-100, -100, 100, 20, 0);
    narrow.floor(-100, 26, 100, 100, 0);  // 6 m (8.5 m along the diagonal legs): a jump
    const auto jump = jetrace::check_drivability(track_of(narrow, diamond()));
    EXPECT_TRUE(jump.empty()) << all(jump);
}

TEST(Drivability, AGateOnABlockIsOnAnObstacle) {
    Mesh m = flat_floor();
    m.block(-60, 0, 3, 0, 10);  // 10 m tall under gate 2, whose centre is 6 m up
    const auto ws = jetrace::check_drivability(track_of(m, diamond()));
    const DrivabilityWarning* w = find(ws, jetrace::kGateOnObstacle, 2);
    ASSERT_NE(w, nullptr) << all(ws);
    EXPECT_NE(w->message.find("is 4.0 m above its centre"), std::string::npos) << w->message;
}

TEST(Drivability, AGateHighAboveTheRoadHangsAboveIt) {
    auto gates = diamond();
    gates[3] = gate(0, -60, 1, 1, 0, 8.0);  // bottom edge 8 m above the road
    const auto ws = jetrace::check_drivability(track_of(flat_floor(), gates));
    const DrivabilityWarning* w = find(ws, jetrace::kGateAboveRoad, 3);
    ASSERT_NE(w, nullptr) << all(ws);
    EXPECT_NE(w->message.find("its bottom edge is 8.0 m above the road"), std::string::npos) << w->message;
    EXPECT_EQ(ws.size(), 1u) << all(ws);
    gates[3] = gate(0, -60, 1, 1, 0, 2.0);  // a car's centre, 2.5 m up, still passes through
    EXPECT_TRUE(jetrace::check_drivability(track_of(flat_floor(), gates)).empty());
}

TEST(Drivability, ASpawnOnASlopeSteeperThanTheRideLimitIsFlagged) {
    Mesh m = flat_floor();
    // A 60 degree bank rising towards -x, 30 m from x = 80 to x = 100, and a 30 degree one at z > 50.
    const double t60 = std::tan(60.0 * 3.14159265358979 / 180.0), t30 = std::tan(30.0 * 3.14159265358979 / 180.0);
    m.quad(Vec3(80, 0, -30), Vec3(80, 0, -10), Vec3(70, 10 * t60, -10), Vec3(70, 10 * t60, -30));
    m.quad(Vec3(80, 0, 50), Vec3(80, 0, 70), Vec3(70, 10 * t30, 70), Vec3(70, 10 * t30, 50));
    auto on_bank = [](double z, double deg) {
        const double a = deg * 3.14159265358979 / 180.0;
        const Vec3 n(std::sin(a), std::cos(a), 0);  // faces +x and up
        return Pose{Vec3(75, 5 * std::tan(a), z) + n * kRest_m, Vec3(0, 0, 1), n};
    };
    const auto ws = jetrace::check_drivability(track_of(m, diamond(), {flat_spawn(), on_bank(-20, 60), on_bank(60, 30)}));
    const DrivabilityWarning* w = find(ws, jetrace::kSpawnTooSteep, 1);
    ASSERT_NE(w, nullptr) << all(ws);
    EXPECT_EQ(w->subject, "spawn");
    EXPECT_NE(w->message.find("sloping 60 degrees"), std::string::npos) << w->message;
    EXPECT_EQ(ws.size(), 1u) << all(ws);  // not the 30 degree one
}

TEST(Drivability, ARespawnOnASteepFaceIsFlaggedOnlyWhenTheNextGateIsUphill) {
    // A 60 degree face centred 20 m above gate 1 (above its opening) holds
    // gate 1's respawn; gate 2's road is on the floor (downhill) or put 40 m up.
    Mesh m = flat_floor();
    const double t60 = std::tan(60.0 * 3.14159265358979 / 180.0);
    m.quad(Vec3(5, 20 - 5 * t60, 50), Vec3(5, 20 - 5 * t60, 70), Vec3(-5, 20 + 5 * t60, 70),
           Vec3(-5, 20 + 5 * t60, 50));
    auto gates = diamond();
    const Vec3 n = Vec3(t60, 1, 0).normalized();
    gates[1].respawn = Pose{Vec3(0, 20, 60) + n * kRest_m, Vec3(0, 0, 1), n};
    const auto down = jetrace::check_drivability(track_of(m, gates));
    EXPECT_EQ(find(down, jetrace::kSpawnTooSteep, 1), nullptr) << all(down);
    gates[2].respawn.position.y() = 40;
    const auto up = jetrace::check_drivability(track_of(m, gates));
    const DrivabilityWarning* w = find(up, jetrace::kSpawnTooSteep, 1);
    ASSERT_NE(w, nullptr) << all(up);
    EXPECT_EQ(w->subject, "respawn");
    EXPECT_NE(w->message.find("sloping 60 degrees"), std::string::npos) << w->message;
}

TEST(Drivability, FloorsWoundDownwardsAreCountedAndStillDriven) {
    Mesh m;
    m.floor(-100, -100, 100, 100, 0, true);
    const auto ws = jetrace::check_drivability(track_of(m, diamond()));
    ASSERT_EQ(ws.size(), 1u) << all(ws);  // the legs, gates and spawn read faces either way
    EXPECT_EQ(ws[0].kind, jetrace::kFacesPointDown);
    EXPECT_EQ(ws[0].index, -1);
    EXPECT_NE(ws[0].message.find("800 of 800 faces (100.0 %, over 25 %)"), std::string::npos) << ws[0].message;
}

TEST(Drivability, AnImplausibleSizeIsFlagged) {
    Mesh tall = flat_floor();
    tall.quad(Vec3(-100, 0, 100), Vec3(-100, 2000, 100), Vec3(-99, 2000, 100), Vec3(-99, 0, 100));  // a 2 km pole
    auto ws = jetrace::check_drivability(track_of(tall, diamond()));
    ASSERT_NE(find(ws, jetrace::kHeightRange, -1), nullptr) << all(ws);
    EXPECT_NE(find(ws, jetrace::kHeightRange, -1)->message.find("2000.0 m tall and 200.0 m wide"), std::string::npos);

    Mesh huge = flat_floor();
    huge.quad(Vec3(-100, 0, 100), Vec3(-100, 0, 200'000), Vec3(-90, 0, 200'000), Vec3(-90, 0, 100));
    ws = jetrace::check_drivability(track_of(huge, diamond()));
    ASSERT_NE(find(ws, jetrace::kHeightRange, -1), nullptr) << all(ws);
    EXPECT_NE(find(ws, jetrace::kHeightRange, -1)->message.find("spans 200.1 km"), std::string::npos);
}

TEST(Drivability, CoordinatesThatAreNotFiniteGiveOneWarningAndNoCrash) {
    Mesh m = flat_floor();
    m.quad(Vec3(0, 0, 0), Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 1), Vec3(1, 0, 1), Vec3(1, 0, 0));
    auto ws = jetrace::check_drivability(track_of(m, diamond()));
    ASSERT_EQ(ws.size(), 1u) << all(ws);
    EXPECT_EQ(ws[0].kind, jetrace::kHeightRange);
    // A gate or spawn that is not finite is skipped; the rest is checked.
    auto gates = diamond();
    gates[2].center.x() = std::numeric_limits<double>::infinity();
    gates[2].respawn.position.y() = std::numeric_limits<double>::quiet_NaN();
    Pose bad = flat_spawn();
    bad.position.z() = std::numeric_limits<double>::quiet_NaN();
    ws = jetrace::check_drivability(track_of(flat_floor(), gates, {flat_spawn(), bad}));
    EXPECT_TRUE(ws.empty()) << all(ws);
}
