// Compiled tracks (.jtrack): built from ring, stadium and a real level, read
// back with the same triangles, gates, spawns and identity, raced to the
// same state hash as the source; corrupt and truncated files refused with a
// message naming the problem. About 5 s (the real level's manifest load).
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/core/crc32c.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"
#include "jetrace/tracks/jtrack.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <unistd.h>

namespace {

using jetrace::same_bits;
using jetrace::Track;
using Bytes = std::vector<std::uint8_t>;

Track builtin(const char* name) {
    Track t;
    EXPECT_TRUE(jetrace::make_builtin_track(name, t));
    return t;
}

// Every field the physics reads, bit for bit.
void expect_same(const Track& a, const Track& b) {
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.identity(), b.identity());
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    for (std::size_t i = 0; i < a.triangles.size(); ++i) {
        const jetrace::Triangle& x = a.triangles[i];
        const jetrace::Triangle& y = b.triangles[i];
        ASSERT_TRUE(same_bits(x.a, y.a) && same_bits(x.b, y.b) && same_bits(x.c, y.c) &&
                    same_bits(x.normal(), y.normal()) && x.degenerate == y.degenerate && x.thin == y.thin)
            << "triangle " << i;
    }
    EXPECT_TRUE(same_bits(a.bounds.min, b.bounds.min) && same_bits(a.bounds.max, b.bounds.max));
    EXPECT_EQ(std::bit_cast<std::uint64_t>(a.kill_height_m), std::bit_cast<std::uint64_t>(b.kill_height_m));
}

Track round_trip(const Track& t) {
    Track back;
    std::string error;
    EXPECT_TRUE(jetrace::decode_jtrack(jetrace::encode_jtrack(t), back, error)) << error;
    return back;
}

std::uint64_t race_hash(Track t) {
    const jetrace::Scene scene = jetrace::Scene::make(std::move(t), jetrace::PhysicsSettings{});
    jetrace::WorldState w = jetrace::start_race(scene, 4, 1);
    jetrace::StepScratch scratch;
    jetrace::run_ai(jetrace::Course(scene), w, jetrace::skills_for(4, 7), 600, false, scratch);
    return jetrace::state_hash(w);
}

// The error decoding `b` gives (empty if it decodes).
std::string decode_error(const Bytes& b) {
    Track t;
    std::string error;
    if (jetrace::decode_jtrack(b, t, error)) return {};
    EXPECT_FALSE(error.empty());
    return error;
}

void put_u32(Bytes& b, std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
}

// Re-seals both checksums, so that only the damage under test remains.
void reseal(Bytes& b) {
    put_u32(b, 56, jetrace::crc32c(std::span<const std::uint8_t>(b).subspan(64)));
    put_u32(b, 60, jetrace::crc32c(std::span<const std::uint8_t>(b.data(), 60)));
}

std::string temp_path(const char* name) {
    return (std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_" + name)).string();
}

TEST(Jtrack, BuiltinTracksRoundTripBitForBit) {
    for (const char* name : {"ring", "stadium"}) {
        const Track t = builtin(name);
        expect_same(t, round_trip(t));
        EXPECT_EQ(jetrace::encode_jtrack(t), jetrace::encode_jtrack(round_trip(t))) << "deterministic bytes";
    }
}

TEST(Jtrack, VerticesAreShared) {
    const Track t = builtin("stadium");
    const Bytes b = jetrace::encode_jtrack(t);
    std::uint32_t vertices = 0;
    std::memcpy(&vertices, b.data() + 28, 4);
    EXPECT_LT(vertices, t.triangles.size()) << "a closed mesh has about half as many vertices as triangles";
}

TEST(Jtrack, RaceOnCompiledTrackHasTheSourceStateHash) {
    const Track ring = builtin("ring");
    EXPECT_EQ(race_hash(ring), race_hash(round_trip(ring)));
    const Track stadium = builtin("stadium");
    EXPECT_EQ(race_hash(stadium), race_hash(round_trip(stadium)));
}

TEST(Jtrack, RealLevelThroughFileAndLoadTrack) {
    const std::string manifest = std::string(JETRACE_SOURCE_DIR) + "/docs/tracks/truck_town.track.json";
    Track source;
    std::string error;
    ASSERT_TRUE(jetrace::load_track(manifest, source, error)) << error;
    const std::string path = temp_path("truck_town.jtrack");
    ASSERT_TRUE(jetrace::write_jtrack_file(source, path, error)) << error;
    Track loaded;
    jetrace::TrackReport report;
    ASSERT_TRUE(jetrace::load_track_report(path, loaded, report, error)) << error;
    EXPECT_EQ(report.format, "jtrack");
    expect_same(source, loaded);
    EXPECT_EQ(race_hash(source), race_hash(loaded));
    // Recognised by its magic under any name.
    const std::string other = temp_path("truck_town.bin");
    std::filesystem::copy_file(path, other, std::filesystem::copy_options::overwrite_existing);
    Track by_magic;
    ASSERT_TRUE(jetrace::load_track(other, by_magic, error)) << error;
    EXPECT_EQ(by_magic.identity(), source.identity());
    std::filesystem::remove(path);
    std::filesystem::remove(other);
}

TEST(Jtrack, EveryTruncationIsRefused) {
    const Bytes full = jetrace::encode_jtrack(builtin("ring"));
    for (std::size_t n = 0; n < full.size(); n += (n < 256 ? 1 : 97)) {
        const std::string e = decode_error(Bytes(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n)));
        ASSERT_FALSE(e.empty()) << "prefix of " << n << " bytes decoded";
        if (n >= 64) {
            ASSERT_NE(e.find("truncated"), std::string::npos) << n << ": " << e;
        }
    }
    Bytes longer = full;
    longer.push_back(0);
    EXPECT_NE(decode_error(longer).find("truncated or padded"), std::string::npos);
}

TEST(Jtrack, EveryFlippedByteIsRefused) {
    const Bytes full = jetrace::encode_jtrack(builtin("ring"));
    for (std::size_t i = 0; i < full.size(); i += (i < 64 ? 1 : 13)) {
        Bytes b = full;
        b[i] ^= 0x10;
        ASSERT_FALSE(decode_error(b).empty()) << "byte " << i;
    }
    Bytes body = full;
    body[100] ^= 1;
    EXPECT_NE(decode_error(body).find("payload checksum mismatch"), std::string::npos);
    Bytes head = full;
    head[20] ^= 1;
    EXPECT_NE(decode_error(head).find("header checksum mismatch"), std::string::npos);
}

TEST(Jtrack, ResealedDamageIsNamed) {
    const Bytes full = jetrace::encode_jtrack(builtin("ring"));
    std::uint32_t name = 0, vertices = 0;
    std::memcpy(&name, full.data() + 24, 4);
    std::memcpy(&vertices, full.data() + 28, 4);
    const std::size_t vertex0 = 64 + ((name + 7) & ~7u);
    const std::size_t index0 = vertex0 + 24u * vertices;

    Bytes b = full;
    put_u32(b, index0 + 4, vertices);  // triangle 0's second corner
    reseal(b);
    EXPECT_NE(decode_error(b).find("triangle 0 uses vertex " + std::to_string(vertices)), std::string::npos)
        << decode_error(b);

    b = full;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::memcpy(b.data() + vertex0 + 24 + 8, &nan, 8);  // vertex 1's y
    reseal(b);
    EXPECT_NE(decode_error(b).find("vertex 1 has a coordinate"), std::string::npos) << decode_error(b);

    b = full;
    put_u32(b, 8, 2);
    reseal(b);
    EXPECT_NE(decode_error(b).find("unsupported version 2"), std::string::npos);

    b = full;
    put_u32(b, 32, 5'000'000);
    reseal(b);
    EXPECT_NE(decode_error(b).find("exceed the limit"), std::string::npos);

    b = full;
    put_u32(b, 36, 1);  // one gate: the sizes no longer add up
    reseal(b);
    EXPECT_NE(decode_error(b).find("its counts make"), std::string::npos) << decode_error(b);

    Bytes garbage(200, 'x');
    EXPECT_NE(decode_error(garbage).find("bad magic"), std::string::npos);
}

TEST(Jtrack, FileErrorsNameThePath) {
    Track t;
    std::string error;
    EXPECT_FALSE(jetrace::load_track("/nonexistent/x.jtrack", t, error));
    EXPECT_NE(error.find("/nonexistent/x.jtrack"), std::string::npos) << error;
    const std::string path = temp_path("short.jtrack");
    std::ofstream(path, std::ios::binary) << "JTRACK\r\n";
    EXPECT_FALSE(jetrace::load_track(path, t, error));
    EXPECT_NE(error.find("shorter than the 64-byte"), std::string::npos) << error;
    // A (sparse) file larger than any valid one is refused before it is mapped.
    std::filesystem::resize_file(path, 400'000'000);
    EXPECT_FALSE(jetrace::load_track(path, t, error));
    EXPECT_NE(error.find("larger than any valid .jtrack"), std::string::npos) << error;
    EXPECT_FALSE(jetrace::write_jtrack_file(builtin("ring"), "/nonexistent/dir/x.jtrack", error));
    EXPECT_NE(error.find("cannot create"), std::string::npos) << error;
    std::filesystem::remove(path);
}

}  // namespace

namespace {

// The checksum the format uses, computed whole and continued piece by piece
// over every split of a buffer (its 8-byte steps and its byte tail).
TEST(Jtrack, Crc32cContinuesAcrossAnySplit) {
    std::vector<std::uint8_t> b(67);
    for (std::size_t i = 0; i < b.size(); ++i) b[i] = static_cast<std::uint8_t>(i * 37 + 11);
    const std::uint32_t whole = jetrace::crc32c(b);
    std::uint32_t bytewise = 0;
    for (std::uint8_t x : b) bytewise = jetrace::crc32c(std::span<const std::uint8_t>(&x, 1), bytewise);
    EXPECT_EQ(whole, bytewise);
    for (std::size_t cut = 0; cut <= b.size(); ++cut) {
        const std::span<const std::uint8_t> s(b);
        EXPECT_EQ(jetrace::crc32c(s.subspan(cut), jetrace::crc32c(s.first(cut))), whole) << cut;
    }
}

// crc32c (the processor's instruction where it has one) and the tables
// agree on every length and start within a buffer, and continued.
TEST(Jtrack, Crc32cInstructionAndTablesAgree) {
    std::vector<std::uint8_t> b(600);
    for (std::size_t i = 0; i < b.size(); ++i) b[i] = static_cast<std::uint8_t>((i * 2654435761u) >> 13);
    const std::span<const std::uint8_t> s(b);
    for (std::size_t start = 0; start < 9; ++start) {
        for (std::size_t len = 0; start + len <= b.size(); len += 1 + len / 8) {
            const std::span<const std::uint8_t> part = s.subspan(start, len);
            ASSERT_EQ(jetrace::crc32c(part), jetrace::crc32c_tables(part)) << start << "+" << len;
            ASSERT_EQ(jetrace::crc32c(part, 0x12345678u), jetrace::crc32c_tables(part, 0x12345678u))
                << start << "+" << len << ", continued";
        }
    }
    const std::string nine = "123456789";
    EXPECT_EQ(jetrace::crc32c_tables({reinterpret_cast<const std::uint8_t*>(nine.data()), nine.size()}),
              0xE3069283u);
}

}  // namespace
