// Wavefront OBJ import/export (docs/TRACKS.md).
#include "jetrace/tracks/builtin_tracks.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace jetrace;

namespace {

constexpr double kRest = 2.5 + 1.0 / 1024.0;

// Pieces of a minimal track; faces use relative indices so pieces compose.
const std::string kFloor =
    "g track\n"
    "v -50 0 -50\nv -50 0 50\nv 50 0 50\nv 50 0 -50\n"
    "f -4 -3 -2 -1\n";
// Vertical gate across x = 0, travel +X, 20 m wide, 20 m tall, centre (0, 10, 0).
const std::string kGate0 =
    "g checkpoint_0\n"
    "v 0 0 -10\nv 0 20 -10\nv 0 20 10\nv 0 0 10\n"
    "f -4 -3 -2 -1\n";
std::string gate(const std::string& group, double x) {
    const std::string xs = std::to_string(x);
    return "g " + group + "\nv " + xs + " 0 -5\nv " + xs + " 8 -5\nv " + xs + " 8 5\nv " + xs + " 0 5\nf -4 -3 -2 -1\n";
}
const std::string kGate1 = gate("checkpoint_1", 20);
// Centroid (-10, 0, 0), first vertex ahead along +X.
const std::string kSpawn0 =
    "o spawn_0\n"
    "v -8 0 0\nv -11 0 1\nv -11 0 -1\n"
    "f -3 -2 -1\n";
const std::string kValid = kFloor + kGate0 + kGate1 + kSpawn0;

void expect_near(const Vec3& a, const Vec3& b, double tol) {
    EXPECT_NEAR(a.x(), b.x(), tol);
    EXPECT_NEAR(a.y(), b.y(), tol);
    EXPECT_NEAR(a.z(), b.z(), tol);
}

// Imports `text`, expects failure and returns the message.
std::string fails(const std::string& text) {
    Track t;
    std::string error;
    EXPECT_FALSE(import_obj(text, "bad", t, error)) << text;
    EXPECT_FALSE(error.empty());
    return error;
}

void round_trip(const std::string& name) {
    Track t;
    ASSERT_TRUE(make_builtin_track(name, t));
    const std::string text = export_obj(t);
    Track u;
    std::string error;
    ASSERT_TRUE(import_obj(text, t.name, u, error)) << error;
    EXPECT_EQ(u.name, t.name);
    ASSERT_EQ(u.triangles.size(), t.triangles.size());
    for (std::size_t i = 0; i < t.triangles.size(); ++i) {
        ASSERT_EQ(u.triangles[i].a, t.triangles[i].a) << i;
        ASSERT_EQ(u.triangles[i].b, t.triangles[i].b) << i;
        ASSERT_EQ(u.triangles[i].c, t.triangles[i].c) << i;
    }
    ASSERT_EQ(u.checkpoints.size(), t.checkpoints.size());
    for (std::size_t i = 0; i < t.checkpoints.size(); ++i) {
        SCOPED_TRACE("checkpoint " + std::to_string(i));
        const Checkpoint &a = u.checkpoints[i], &b = t.checkpoints[i];
        expect_near(a.center, b.center, 1e-6);
        expect_near(a.normal, b.normal, 1e-9);
        expect_near(a.across, b.across, 1e-9);
        expect_near(a.up, b.up, 1e-9);
        EXPECT_NEAR(a.half_width_m, b.half_width_m, 1e-9);
        EXPECT_NEAR(a.half_height_m, b.half_height_m, 1e-9);
        expect_near(a.respawn.position, b.respawn.position, 1e-9);
        expect_near(a.respawn.forward, b.respawn.forward, 1e-9);
        expect_near(a.respawn.up, b.respawn.up, 1e-9);
    }
    ASSERT_EQ(u.spawns.size(), t.spawns.size());
    for (std::size_t i = 0; i < t.spawns.size(); ++i) {
        SCOPED_TRACE("spawn " + std::to_string(i));
        expect_near(u.spawns[i].position, t.spawns[i].position, 1e-9);
        expect_near(u.spawns[i].forward, t.spawns[i].forward, 1e-9);
        expect_near(u.spawns[i].up, t.spawns[i].up, 1e-9);
    }
    EXPECT_EQ(u.kill_height_m, t.kill_height_m);
}

}  // namespace

TEST(ObjImport, RoundTripStadium) { round_trip("stadium"); }
TEST(ObjImport, RoundTripRing) { round_trip("ring"); }

TEST(ObjImport, MinimalTrack) {
    Track t;
    std::string error;
    ASSERT_TRUE(import_obj(kValid, "mini", t, error)) << error;
    EXPECT_EQ(t.name, "mini");
    ASSERT_EQ(t.triangles.size(), 2u);
    ASSERT_EQ(t.checkpoints.size(), 2u);
    const Checkpoint& g0 = t.checkpoints[0];
    expect_near(g0.center, Vec3(0, 10, 0), 1e-12);
    expect_near(g0.normal, Vec3(1, 0, 0), 1e-12);
    expect_near(g0.up, Vec3(0, 1, 0), 1e-12);
    expect_near(g0.across, Vec3(0, 0, 1), 1e-12);
    EXPECT_NEAR(g0.half_width_m, 10, 1e-12);
    EXPECT_NEAR(g0.half_height_m, 10, 1e-12);
    expect_near(g0.respawn.position, Vec3(0, kRest, 0), 1e-12);
    expect_near(g0.respawn.forward, Vec3(1, 0, 0), 1e-12);
    expect_near(g0.respawn.up, Vec3(0, 1, 0), 1e-12);
    const Checkpoint& g1 = t.checkpoints[1];
    expect_near(g1.center, Vec3(20, 4, 0), 1e-12);
    EXPECT_NEAR(g1.half_width_m, 5, 1e-12);
    EXPECT_NEAR(g1.half_height_m, 4, 1e-12);
    expect_near(g1.respawn.position, Vec3(20, kRest, 0), 1e-12);
    ASSERT_EQ(t.spawns.size(), 1u);
    expect_near(t.spawns[0].position, Vec3(-10, kRest, 0), 1e-12);
    expect_near(t.spawns[0].forward, Vec3(1, 0, 0), 1e-12);
    expect_near(t.spawns[0].up, Vec3(0, 1, 0), 1e-12);
    EXPECT_EQ(t.kill_height_m, -50.0);
}

TEST(ObjImport, KillHeightGroupAndCrlfAndNumberedNames) {
    const std::string wall = "g track.wall\nv 50 0 -50\nv 50 0 50\nv 50 5 50\nf -3 -2 -1\n";
    const std::string kill = "g kill_height\nv 0 -7.5 0\nv 1 -7 0\nv 0 -7 1\nf -3 -2 -1\n";
    const std::string text = kFloor + wall + kGate0 + gate("checkpoint_01", 20) + kSpawn0 + kill;
    std::string crlf;
    for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    Track t;
    std::string error;
    ASSERT_TRUE(import_obj(crlf, "k", t, error)) << error;
    EXPECT_EQ(t.triangles.size(), 3u);
    EXPECT_EQ(t.kill_height_m, -7.5);
    EXPECT_EQ(t.checkpoints.size(), 2u);
}

TEST(ObjImport, CoordinatesAreReadExactly) {
    // 1000.123 and 0.1 must be the nearest doubles, as std::strtod gives them.
    std::string text = kValid + "g track_extra\nv 1000.123 0.1 -3\nv 1000.123 0.1 3\nv 1001 0.1 0\nf -3 -2 -1\n";
    Track t;
    std::string error;
    ASSERT_TRUE(import_obj(text, "x", t, error)) << error;
    ASSERT_EQ(t.triangles.size(), 3u);
    EXPECT_EQ(t.triangles[2].a.x(), std::stod("1000.123"));
    EXPECT_EQ(t.triangles[2].a.y(), std::stod("0.1"));
}

TEST(ObjImport, RejectsEmpty) {
    EXPECT_NE(fails("").find("empty"), std::string::npos);
    EXPECT_NE(fails(" \n\r\n\t").find("empty"), std::string::npos);
}

TEST(ObjImport, RejectsMissingTrackGroup) {
    EXPECT_NE(fails(kGate0 + kGate1 + kSpawn0).find("no 'track' group"), std::string::npos);
}

TEST(ObjImport, RejectsUnknownGroup) {
    const std::string e = fails(kValid + "g chekpoint_2\nv 0 0 0\nv 1 0 0\nv 0 0 1\nf -3 -2 -1\n");
    EXPECT_NE(e.find("unknown group 'chekpoint_2'"), std::string::npos) << e;
    EXPECT_NE(e.find("line 24"), std::string::npos) << e;
}

TEST(ObjImport, RejectsFacesOutsideGroups) {
    const std::string e = fails("v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\n" + kValid);
    EXPECT_NE(e.find("outside any group"), std::string::npos) << e;
}

TEST(ObjImport, RejectsGapInCheckpoints) {
    const std::string e = fails(kFloor + kGate0 + gate("checkpoint_2", 20) + kSpawn0);
    EXPECT_NE(e.find("checkpoint 1 is missing"), std::string::npos) << e;
}

TEST(ObjImport, RejectsDuplicateCheckpoint) {
    const std::string e = fails(kValid + gate("checkpoint_01", 30));
    EXPECT_NE(e.find("duplicate checkpoint 1"), std::string::npos) << e;
}

TEST(ObjImport, RejectsSingleCheckpoint) {
    const std::string e = fails(kFloor + kGate0 + kSpawn0);
    EXPECT_NE(e.find("at least 2 checkpoints"), std::string::npos) << e;
}

TEST(ObjImport, RejectsNoSpawn) {
    const std::string e = fails(kFloor + kGate0 + kGate1);
    EXPECT_NE(e.find("no spawn"), std::string::npos) << e;
}

TEST(ObjImport, RejectsSpawnGap) {
    std::string spawn3 = kSpawn0;
    spawn3.replace(spawn3.find("spawn_0"), 7, "spawn_3");
    const std::string e = fails(kValid + spawn3);
    EXPECT_NE(e.find("spawn 1 is missing"), std::string::npos) << e;
}

TEST(ObjImport, RejectsNonFiniteCoordinates) {
    for (const char* bad : {"nan", "inf", "-inf", "1e999", "abc", "1.5e"}) {
        const std::string e = fails("g track\nv " + std::string(bad) + " 0 0\n" + kValid);
        EXPECT_NE(e.find("line 2"), std::string::npos) << e;
        if (std::string(bad).find('n') != std::string::npos) {
            EXPECT_NE(e.find("finite"), std::string::npos) << e;
        }
    }
    EXPECT_NE(fails("g track\nv 2e6 0 0\n" + kValid).find("exceeds"), std::string::npos);
}

TEST(ObjImport, RejectsOutOfRangeFaceIndices) {
    EXPECT_NE(fails(kValid + "g track\nf 1 2 99\n").find("out of range"), std::string::npos);
    EXPECT_NE(fails(kValid + "g track\nf 1 2 -99\n").find("out of range"), std::string::npos);
    EXPECT_NE(fails(kValid + "g track\nf 1 2 99999999999999\n").find("out of range"), std::string::npos);
    EXPECT_NE(fails(kValid + "g track\nf 1 2 0\n").find("index 0"), std::string::npos);
    EXPECT_NE(fails(kValid + "g track\nf 1 2\n").find("at least 3"), std::string::npos);
}

TEST(ObjImport, RejectsGateWithoutSurfaceBelow) {
    const std::string e = fails(kFloor + kGate0 + gate("checkpoint_1", 200) + kSpawn0);
    EXPECT_NE(e.find("checkpoint 1 has no track surface below"), std::string::npos) << e;
}

TEST(ObjImport, RejectsHorizontalGate) {
    const std::string flat = "g checkpoint_1\nv 10 5 -5\nv 10 5 5\nv 20 5 5\nv 20 5 -5\nf -4 -3 -2 -1\n";
    const std::string e = fails(kFloor + kGate0 + flat + kSpawn0);
    EXPECT_NE(e.find("horizontal"), std::string::npos) << e;
}

TEST(ObjImport, RejectsMalformedGatesAndSpawns) {
    const std::string tri = "g checkpoint_1\nv 10 0 -5\nv 10 8 -5\nv 10 8 5\nf -3 -2 -1\n";
    EXPECT_NE(fails(kFloor + kGate0 + tri + kSpawn0).find("exactly one quad"), std::string::npos);
    const std::string spawn_off = "g spawn_0\nv 500 0 0\nv 499 0 1\nv 499 0 -1\nf -3 -2 -1\n";
    EXPECT_NE(fails(kFloor + kGate0 + kGate1 + spawn_off).find("spawn 0 has no track surface"), std::string::npos);
    EXPECT_NE(fails(kValid + "g track floor\nf 1 2 3\n").find("several words"), std::string::npos);
    EXPECT_NE(fails(kValid + "g checkpoint_x\nf 1 2 3\n").find("checkpoint_<number>"), std::string::npos);
}

TEST(ObjImport, ReportsParserErrors) {
    // A zero texture index is caught by tinyobjloader itself; its text is kept.
    const std::string e = fails(kValid + "g track\nf 1/0 2/0 3/0\n");
    EXPECT_NE(e.find("OBJ parser"), std::string::npos) << e;
}

TEST(ObjImport, RejectsBinaryGarbage) {
    std::string text = kValid;
    text[5] = '\0';
    EXPECT_NE(fails(text).find("NUL"), std::string::npos);
}
