// Track manifests (docs/TRACKS.md, "Track manifests"): gates and spawns
// generated from a route on a mesh made here, explicit gates, and every
// check's message (a gate wound against the route, out of order, off the
// road, under a roof; low clearance on the route; degenerate triangles).
#include "jetrace/tracks/track_io.hpp"
#include "jetrace/tracks/track_manifest.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace jetrace;

namespace {

constexpr double kRest = 2.5 + 1.0 / 1024.0;

void expect_near(const Vec3& a, const Vec3& b) {
    EXPECT_NEAR(a.x(), b.x(), 1e-9);
    EXPECT_NEAR(a.y(), b.y(), 1e-9);
    EXPECT_NEAR(a.z(), b.z(), 1e-9);
}

// A horizontal rectangle [x0, x1] x [z0, z1] at height y, two triangles facing up.
void quad(MeshPart& p, double x0, double x1, double z0, double z1, double y) {
    p.corners.insert(p.corners.end(), {{x0, y, z0}, {x0, y, z1}, {x1, y, z1}, {x0, y, z0}, {x1, y, z1}, {x1, y, z0}});
}

ImportedMesh floor_mesh() {
    ImportedMesh m;
    MeshPart floor{"Floor", {}};
    quad(floor, -100, 100, -100, 100, 0);
    m.parts.push_back(floor);
    return m;
}

void add_part(ImportedMesh& m, const std::string& name, double x0, double x1, double z0, double z1, double y) {
    MeshPart p{name, {}};
    quad(p, x0, x1, z0, z1, y);
    m.parts.push_back(p);
}

// A 480 m square loop starting at (-60, -60), first heading +X.
TrackManifest square() {
    TrackManifest m;
    m.name = "square";
    m.meshes = {"generated"};
    m.route = {{-60, -60, {}}, {60, -60, {}}, {60, 60, {}}, {-60, 60, {}}};
    return m;
}

std::string fails(const TrackManifest& m, const ImportedMesh& mesh) {
    Track t;
    TrackReport r;
    std::string error;
    EXPECT_FALSE(build_manifest_track(m, {mesh}, t, r, error));
    return error;
}

ManifestGate gate_at(double x, double z, Vec3 dir) {
    ManifestGate g;
    g.position = {x, z, {}};
    g.direction = dir;
    return g;
}

}  // namespace

TEST(TrackManifest, RouteGivesGatesAndSpawns) {
    Track t;
    TrackReport r;
    std::string error;
    ASSERT_TRUE(build_manifest_track(square(), {floor_mesh()}, t, r, error)) << error;
    EXPECT_TRUE(validate(t).empty());
    ASSERT_EQ(t.checkpoints.size(), 12u);  // 480 m / 40 m
    const Checkpoint& g0 = t.checkpoints[0];
    expect_near(g0.center, Vec3(-60, 6, -60));  // no walls: full 30 m width, 12 m height
    EXPECT_EQ(g0.normal, Vec3(1, 0, 0));
    EXPECT_EQ(g0.half_width_m, 15);
    EXPECT_EQ(g0.half_height_m, 6);
    EXPECT_NEAR(g0.respawn.position.y(), kRest, 1e-12);
    expect_near(t.checkpoints[3].center, Vec3(60, 6, -60));
    EXPECT_EQ(t.checkpoints[3].normal, Vec3(0, 0, 1));
    ASSERT_EQ(t.spawns.size(), 8u);
    // Pole: 12 m behind the start on the last leg (heading -Z), 3 m to its left.
    EXPECT_NEAR(t.spawns[0].position.x(), -63, 1e-9);
    EXPECT_NEAR(t.spawns[0].position.z(), -48, 1e-9);
    EXPECT_NEAR(t.spawns[0].position.y(), kRest, 1e-9);
    EXPECT_EQ(t.spawns[0].forward, Vec3(0, 0, -1));
    EXPECT_NEAR(t.spawns[1].position.x(), -57, 1e-9);
    EXPECT_NEAR(t.spawns[2].position.z(), -38, 1e-9);
    EXPECT_NEAR(r.route_length_m, 480, 1e-6);
    EXPECT_TRUE(r.warnings.empty());
    EXPECT_EQ(t.kill_height_m, -50);
    // The same input gives the same track.
    Track again;
    ASSERT_TRUE(build_manifest_track(square(), {floor_mesh()}, again, r, error));
    EXPECT_EQ(again.identity(), t.identity());
}

TEST(TrackManifest, GatesNarrowToTheRoadBetweenWalls) {
    ImportedMesh mesh = floor_mesh();
    MeshPart wall{"Wall", {}};
    // A wall along z = -52 (8 m to the right of the first leg, which heads +X).
    wall.corners = {{-100, 0, -52}, {100, 0, -52}, {100, 20, -52}, {-100, 0, -52}, {100, 20, -52}, {-100, 20, -52}};
    mesh.parts.push_back(wall);
    Track t;
    TrackReport r;
    std::string error;
    ASSERT_TRUE(build_manifest_track(square(), {mesh}, t, r, error)) << error;
    // across = normal x up = (0, 0, 1): right 8 m (wall), left 15 m (cap).
    EXPECT_NEAR(t.checkpoints[0].half_width_m, 11.5, 1e-9);
    EXPECT_NEAR(t.checkpoints[0].center.z(), -63.5, 1e-9);
}

TEST(TrackManifest, RoofOverAGateIsRefusedWithItsName) {
    ImportedMesh mesh = floor_mesh();
    add_part(mesh, "Gantry", -25, -15, -70, -50, 3.9);  // over gate 1 at (-20, -60)
    const std::string e = fails(square(), mesh);
    EXPECT_NE(e.find("gate 1 at (-20.0, 0.0, -60.0): 'Gantry' is 3.9 m above the road (a roof, gantry or bridge); "
                     "a car needs 5.0 m"),
              std::string::npos)
        << e;
}

TEST(TrackManifest, LowClearanceBetweenGatesIsAWarningWithItsPosition) {
    ImportedMesh mesh = floor_mesh();
    add_part(mesh, "Bridge", -5, 5, -70, -50, 4.0);  // between gates 1 and 2
    Track t;
    TrackReport r;
    std::string error;
    ASSERT_TRUE(build_manifest_track(square(), {mesh}, t, r, error)) << error;
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("clearance 4.0 m under 'Bridge' at (-4.0, 0.0, -60.0) (route 56.0 m to 66.0 m): a car "
                                 "needs 5.0 m"),
              std::string::npos)
        << r.warnings[0];
}

TEST(TrackManifest, GateOffTheRoadIsRefused) {
    TrackManifest m = square();
    m.route = {{-60, -60, {}}, {160, -60, {}}, {60, 60, {}}};  // leaves the floor
    EXPECT_NE(fails(m, floor_mesh()).find("has no drivable surface under its centre"), std::string::npos);
    TrackManifest g = square();
    g.gates = {gate_at(-60, -60, {1, 0, 0}), gate_at(300, -60, {1, 0, 0})};
    EXPECT_NE(fails(g, floor_mesh()).find("gate 1 at (x 300.0, z -60.0) has no drivable surface under its centre"),
              std::string::npos);
}

TEST(TrackManifest, ExplicitGatesFollowTheRoute) {
    TrackManifest m = square();
    m.gates = {gate_at(-60, -60, {1, 0, 0}), gate_at(60, 0, {0, 0, 1}), gate_at(0, 60, {-1, 0, 0})};
    Track t;
    TrackReport r;
    std::string error;
    ASSERT_TRUE(build_manifest_track(m, {floor_mesh()}, t, r, error)) << error;
    ASSERT_EQ(t.checkpoints.size(), 3u);
    EXPECT_EQ(t.checkpoints[1].normal, Vec3(0, 0, 1));
    EXPECT_EQ(t.spawns.size(), 8u);
}

TEST(TrackManifest, GateWoundAgainstTheRouteIsRefused) {
    TrackManifest m = square();
    m.gates = {gate_at(-60, -60, {1, 0, 0}), gate_at(60, 0, {0, 0, -1}), gate_at(0, 60, {-1, 0, 0})};
    EXPECT_NE(fails(m, floor_mesh()).find("gate 1 at (x 60.0, z 0.0) is wound against the route: its direction is 180 "
                                          "degrees from the route's"),
              std::string::npos);
}

TEST(TrackManifest, GatesOutOfOrderAreRefused) {
    TrackManifest m = square();
    m.gates = {gate_at(-60, -60, {1, 0, 0}), gate_at(0, 60, {-1, 0, 0}), gate_at(60, 0, {0, 0, 1})};
    EXPECT_NE(fails(m, floor_mesh()).find("gate 2 at (x 60.0, z 0.0) is out of order: it lies 180.0 m along the route "
                                          "from gate 0, gate 1 at 300.0 m"),
              std::string::npos);
}

TEST(TrackManifest, DegenerateTrianglesAreDroppedAndReported) {
    ImportedMesh mesh = floor_mesh();
    mesh.parts[0].corners.insert(mesh.parts[0].corners.end(), {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});  // collinear
    Track t;
    TrackReport r;
    std::string error;
    ASSERT_TRUE(build_manifest_track(square(), {mesh}, t, r, error)) << error;
    EXPECT_EQ(t.triangles.size(), 2u);
    EXPECT_EQ(r.source_triangles, 3u);
    EXPECT_EQ(r.degenerate_dropped, 1u);
    ASSERT_FALSE(r.warnings.empty());
    EXPECT_EQ(r.warnings[0], "1 degenerate (zero-area) triangles dropped (the first in 'Floor' at (0.0, 0.0, 0.0))");
}

TEST(TrackManifest, PatternsScaleAndUpAxis) {
    ImportedMesh mesh = floor_mesh();
    add_part(mesh, "TreeLeaves", -5, 5, -70, -50, 2.0);  // would be a roof over gate 1 if kept
    TrackManifest m = square();
    m.ignore = {"Tree*"};
    Track t;
    TrackReport r;
    std::string error;
    ASSERT_TRUE(build_manifest_track(m, {mesh}, t, r, error)) << error;
    EXPECT_EQ(r.ignored_triangles, 2u);
    EXPECT_EQ(t.triangles.size(), 2u);
    // Z up, scaled x2: the floor lies in x, y of the file.
    ImportedMesh zup;
    zup.parts.push_back({"Ground", {{-50, -50, 0}, {50, -50, 0}, {50, 50, 0}, {-50, -50, 0}, {50, 50, 0}, {-50, 50, 0}}});
    TrackManifest mz = square();
    mz.up = 'z';
    mz.scale = 2;
    ASSERT_TRUE(build_manifest_track(mz, {zup}, t, r, error)) << error;
    EXPECT_EQ(t.bounds.min, Vec3(-100, 0, -100));
    EXPECT_EQ(t.bounds.max, Vec3(100, 0, 100));
}

TEST(TrackManifest, JsonKeysAreChecked) {
    TrackManifest m;
    std::string error;
    ASSERT_TRUE(parse_manifest(R"({"mesh": "a.glb", "scale": 2, "route": [[0, 0], [10, 0], [10, 3, 10]],
                                   "ignore": ["Tree*"], "kill_height_m": -20})",
                               "/data", m, error))
        << error;
    EXPECT_EQ(m.meshes, std::vector<std::string>{"/data/a.glb"});
    EXPECT_EQ(m.scale, 2);
    ASSERT_EQ(m.route.size(), 3u);
    EXPECT_EQ(m.route[2].y, 3.0);
    EXPECT_EQ(m.kill_height_m, -20.0);
    EXPECT_FALSE(parse_manifest(R"({"mesh": "a.glb", "rout": []})", "", m, error));
    EXPECT_NE(error.find("unknown key 'rout'"), std::string::npos);
    EXPECT_FALSE(parse_manifest(R"({"mesh": "a.glb", "scale": "2", "route": [[0,0],[1,0],[1,1]]})", "", m, error));
    EXPECT_EQ(error, "'scale' must be a number");
    EXPECT_FALSE(parse_manifest(R"({"mesh": "a.glb"})", "", m, error));
    EXPECT_EQ(error, "the manifest needs a 'route' or 'gates'");
    EXPECT_FALSE(parse_manifest("{", "", m, error));
    EXPECT_EQ(error, "the manifest is not valid JSON");
}
