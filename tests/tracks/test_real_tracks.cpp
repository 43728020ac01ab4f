// The two real levels in the repository (docs/tracks/godot-*: glTF exports of
// other games' maps, with their licences) load through their manifests in
// docs/tracks/.
#include "jetrace/tracks/track_io.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

struct Expected {
    const char* manifest;
    std::size_t source, degenerate, triangles, gates;
};

void check(const Expected& e) {
    const std::string path = std::string(JETRACE_SOURCE_DIR) + "/docs/tracks/" + e.manifest;
    jetrace::Track t;
    jetrace::TrackReport r;
    std::string error;
    ASSERT_TRUE(jetrace::load_track_report(path, t, r, error)) << error;
    EXPECT_EQ(r.format, "manifest");
    EXPECT_EQ(r.source_triangles, e.source);
    EXPECT_EQ(r.degenerate_dropped, e.degenerate);
    EXPECT_EQ(t.triangles.size(), e.triangles);
    EXPECT_EQ(e.source, e.triangles + e.degenerate);
    for (const jetrace::Triangle& tri : t.triangles) ASSERT_FALSE(tri.degenerate);
    ASSERT_FALSE(r.warnings.empty());
    EXPECT_EQ(r.warnings[0].find(std::to_string(e.degenerate) + " degenerate (zero-area) triangles dropped"), 0u)
        << r.warnings[0];
    EXPECT_EQ(t.checkpoints.size(), e.gates);
    EXPECT_EQ(t.spawns.size(), 8u);
    EXPECT_TRUE(jetrace::validate(t).empty());
    // load_track() (what the server, bots and jetrace-sim call) takes the same path.
    jetrace::Track again;
    ASSERT_TRUE(jetrace::load_track(path, again, error)) << error;
    EXPECT_EQ(again.identity(), t.identity());
}

}  // namespace

TEST(RealTracks, TruckTownLoadsThroughItsManifest) { check({"truck_town.track.json", 30477, 136, 30341, 28}); }
TEST(RealTracks, Zdm2LoadsThroughItsManifest) { check({"zdm2.track.json", 58772, 1134, 57638, 10}); }
