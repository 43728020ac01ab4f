// glTF 2.0 import (docs/TRACKS.md, "glTF"): a small file written here, as
// .gltf + .bin and as .glb, against the triangles its node transforms give;
// then malformed files, each refused with its reason.
#include "jetrace/tracks/mesh_import.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace jetrace;
using nlohmann::json;

namespace {

// 4 quad vertices (48 bytes), 6 uint16 indices (12), 3 triangle vertices (36).
std::string buffer_bytes() {
    const float quad[] = {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1};
    const std::uint16_t idx[] = {0, 1, 2, 0, 2, 3};
    const float tri[] = {0, 0, 0, 0, 1, 0, 1, 0, 0};
    std::string b(96, '\0');
    std::memcpy(b.data(), quad, 48);
    std::memcpy(b.data() + 48, idx, 12);
    std::memcpy(b.data() + 60, tri, 36);
    return b;
}

// Root (translated, turned 90 degrees about Y) > Quad (scaled x2, indexed);
// Tri (a matrix moving it up 5 m) with a non-indexed triangle list and a
// LINES primitive, which is skipped.
json document(const json& buffer) {
    const double h = 0.70710678118654752;
    return {{"asset", {{"version", "2.0"}}},
            {"scene", 0},
            {"scenes", {{{"nodes", {0, 2}}}}},
            {"nodes",
             {{{"name", "Root"}, {"translation", {10, 0, 0}}, {"rotation", {0, h, 0, h}}, {"children", {1}}},
              {{"name", "Quad"}, {"scale", {2, 2, 2}}, {"mesh", 0}},
              {{"name", "Tri"}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 5, 0, 1}}, {"mesh", 1}}}},
            {"meshes",
             {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}},
              {{"primitives", {{{"attributes", {{"POSITION", 2}}}}, {{"attributes", {{"POSITION", 2}}}, {"mode", 1}}}}}}},
            {"accessors",
             {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
              {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}},
              {{"bufferView", 2}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}}}},
            {"bufferViews",
             {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
              {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 12}},
              {{"buffer", 0}, {"byteOffset", 60}, {"byteLength", 36}}}},
            {"buffers", {buffer}}};
}

std::string glb(const json& doc, const std::string& bin) {
    std::string j = doc.dump();
    while (j.size() % 4) j += ' ';
    auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    return "glTF" + u32(2) + u32(static_cast<std::uint32_t>(12 + 8 + j.size() + 8 + bin.size())) +
           u32(static_cast<std::uint32_t>(j.size())) + "JSON" + j + u32(static_cast<std::uint32_t>(bin.size())) +
           std::string("BIN\0", 4) + bin;
}

std::filesystem::path temp_dir() {
    const auto d = std::filesystem::temp_directory_path() /
                   ("jetrace_gltf_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                    ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(d);
    return d;
}

void write(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
}

void expect_vec(const Vec3& a, const Vec3& b) {
    EXPECT_NEAR(a.x(), b.x(), 1e-6);
    EXPECT_NEAR(a.y(), b.y(), 1e-6);
    EXPECT_NEAR(a.z(), b.z(), 1e-6);
}

void expect_expected_mesh(const ImportedMesh& m) {
    ASSERT_EQ(m.parts.size(), 2u);
    EXPECT_EQ(m.parts[0].name, "Quad");
    EXPECT_EQ(m.parts[1].name, "Tri");
    EXPECT_EQ(m.skipped_primitives, 1u);
    EXPECT_EQ(m.triangles(), 3u);
    // Quad: p -> turn90(2p) + (10, 0, 0), turn90(x, y, z) = (z, y, -x).
    const std::vector<Vec3> quad = {{10, 0, 0}, {10, 0, -2}, {12, 0, -2}, {10, 0, 0}, {12, 0, -2}, {12, 0, 0}};
    ASSERT_EQ(m.parts[0].corners.size(), quad.size());
    for (std::size_t i = 0; i < quad.size(); ++i) expect_vec(m.parts[0].corners[i], quad[i]);
    const std::vector<Vec3> tri = {{0, 5, 0}, {0, 6, 0}, {1, 5, 0}};
    ASSERT_EQ(m.parts[1].corners.size(), tri.size());
    for (std::size_t i = 0; i < tri.size(); ++i) EXPECT_EQ(m.parts[1].corners[i], tri[i]);  // exact: no rotation
}

std::string refused(const json& doc, const std::string& bin) {
    ImportedMesh m;
    std::string error;
    EXPECT_FALSE(import_gltf_bytes(glb(doc, bin), "", m, error));
    return error;
}

}  // namespace

TEST(GltfImport, GltfWithBinFileGivesTheTransformedTriangles) {
    const auto dir = temp_dir();
    write(dir / "t.bin", buffer_bytes());
    write(dir / "t.gltf", document({{"uri", "t.bin"}, {"byteLength", 96}}).dump());
    ImportedMesh m;
    std::string error;
    ASSERT_TRUE(import_gltf_file((dir / "t.gltf").string(), m, error)) << error;
    expect_expected_mesh(m);
    std::filesystem::remove_all(dir);
}

TEST(GltfImport, GlbGivesTheSameTriangles) {
    const auto dir = temp_dir();
    write(dir / "t.glb", glb(document({{"byteLength", 96}}), buffer_bytes()));
    ImportedMesh m;
    std::string error;
    ASSERT_TRUE(import_gltf_file((dir / "t.glb").string(), m, error)) << error;
    expect_expected_mesh(m);
    // A bare mesh is no race: load_track() asks for a manifest; inspect_track() reads it.
    Track t;
    EXPECT_FALSE(load_track((dir / "t.glb").string(), t, error));
    EXPECT_NE(error.find("track manifest"), std::string::npos) << error;
    TrackReport report;
    ASSERT_TRUE(inspect_track((dir / "t.glb").string(), t, report, error)) << error;
    EXPECT_EQ(t.triangles.size(), 3u);
    EXPECT_EQ(report.skipped_primitives, 1u);
    std::filesystem::remove_all(dir);
}

TEST(GltfImport, AccessorPastItsBufferViewIsRefused) {
    json doc = document({{"byteLength", 96}});
    doc["accessors"][0]["count"] = 5;
    EXPECT_NE(refused(doc, buffer_bytes()).find("reads past the end of its bufferView"), std::string::npos);
}

TEST(GltfImport, BufferViewOutsideItsBufferIsRefused) {
    json doc = document({{"byteLength", 96}});
    doc["bufferViews"][2]["byteLength"] = 1000;
    const std::string e = refused(doc, buffer_bytes());
    EXPECT_FALSE(e.empty());
}

TEST(GltfImport, IndexOutOfRangeIsRefused) {
    std::string bin = buffer_bytes();
    const std::uint16_t bad = 9;
    std::memcpy(bin.data() + 50, &bad, 2);
    EXPECT_NE(refused(document({{"byteLength", 96}}), bin).find("index 9 is out of range"), std::string::npos);
}

TEST(GltfImport, NonFloatPositionsAndCyclesAreRefused) {
    json doc = document({{"byteLength", 96}});
    doc["accessors"][0]["componentType"] = 5123;
    EXPECT_NE(refused(doc, buffer_bytes()).find("is not float"), std::string::npos);
    json cyc = document({{"byteLength", 96}});
    cyc["nodes"][1]["children"] = {0};
    EXPECT_NE(refused(cyc, buffer_bytes()).find("appears twice in the hierarchy"), std::string::npos);
}

TEST(GltfImport, ExternalFilesAreRefusedFromMemoryAndGarbageIsRefused) {
    ImportedMesh m;
    std::string error;
    EXPECT_FALSE(import_gltf_bytes(document({{"uri", "/etc/hostname"}, {"byteLength", 96}}).dump(), "", m, error));
    EXPECT_FALSE(import_gltf_bytes("glTF\x02", "", m, error));
    EXPECT_FALSE(import_gltf_bytes("{\"asset\": 3}", "", m, error));
    EXPECT_FALSE(error.empty());
}

TEST(GltfImport, DeclaredTriangleCountOverTheLimitIsRefusedBeforeReading) {
    json doc = document({{"byteLength", 96}});
    doc["accessors"][1]["count"] = 3 * (kMaxTrackTriangles + 1);  // far past the 12 bytes it has
    EXPECT_NE(refused(doc, buffer_bytes()).find("more than 4000000 triangles in the file"), std::string::npos);
}

TEST(ObjSizeLimits, FaceCountOverTheLimitIsRefusedInThePrePass) {
    std::string text = "g track\nv 0 0 0\nv 1 0 0\nv 0 0 1\n";
    const std::string face = "f 1 2 3\n";
    text.reserve(text.size() + face.size() * (kMaxTrackTriangles + 100'001));
    for (std::size_t i = 0; i < kMaxTrackTriangles + 100'001; ++i) text += face;
    Track t;
    std::string error;
    EXPECT_FALSE(import_obj(text, "big", t, error));
    EXPECT_NE(error.find("too many faces (over 4100000 triangles)"), std::string::npos) << error;
}
