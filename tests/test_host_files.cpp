// jetrace-server's files: name patterns, durable writes, the results JSON
// and the spent-nonce table.
#include "jetrace/server/host_files.hpp"
#include "jetrace/server/path_template.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace js = jetrace::server;
namespace fs = std::filesystem;

namespace {

struct TempDir {
    fs::path path;
    TempDir() {
        char tmpl[] = "/tmp/jetrace-host-files-XXXXXX";
        path = ::mkdtemp(tmpl);
    }
    ~TempDir() { fs::remove_all(path); }
};

std::string read(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

TEST(HostFiles, ExpandsRaceNumberAndStartTime) {
    const std::int64_t t = 1796166900;  // 2026-12-01T23:15:00Z
    EXPECT_EQ(js::utc_compact(t), "20261201T231500Z");
    EXPECT_EQ(js::utc_iso8601(t), "2026-12-01T23:15:00Z");
    EXPECT_EQ(js::expand_path("r-%n-%t.json", 7, t), "r-7-20261201T231500Z.json");
    EXPECT_EQ(js::expand_path("100%%-%x-%", 1, t), "100%-%x-%");
    EXPECT_TRUE(js::path_varies("r-%n.json"));
    EXPECT_TRUE(js::path_varies("r-%t.json"));
    EXPECT_FALSE(js::path_varies("r-%%n.json"));
    EXPECT_FALSE(js::path_varies("results.json"));
}

TEST(HostFiles, WritesAtomicallyAndSaysWhatFailed) {
    TempDir dir;
    std::string error;
    const std::string path = (dir.path / "a.json").string();
    ASSERT_TRUE(js::write_file_atomically(path, "one\n", error)) << error;
    ASSERT_TRUE(js::write_file_atomically(path, "two\n", error)) << error;
    EXPECT_EQ(read(path), "two\n");
    EXPECT_FALSE(fs::exists(path + ".tmp"));
    const std::string missing = (dir.path / "no" / "a.json").string();
    EXPECT_FALSE(js::write_file_atomically(missing, "x", error));
    EXPECT_NE(error.find("'" + missing + "': No such file or directory"), std::string::npos) << error;
}

TEST(HostFiles, ChecksThatFilesCanBeCreated) {
    TempDir dir;
    std::string error;
    EXPECT_TRUE(js::check_can_create((dir.path / "r.json").string(), error)) << error;
    EXPECT_TRUE(fs::is_empty(dir.path));  // the probe is gone
    EXPECT_FALSE(js::check_can_create(dir.path.string(), error));
    EXPECT_NE(error.find("is a directory"), std::string::npos) << error;
    EXPECT_FALSE(js::check_can_create((dir.path / "no" / "r.json").string(), error));
    EXPECT_NE(error.find("No such file or directory"), std::string::npos) << error;
}

TEST(HostFiles, ResultsListEveryRacer) {
    js::RaceEnd end;
    end.race_number = 2;
    end.ticks = 100;
    end.reason = jetrace::replay::EndReason::drained;
    end.start_unix_s = 1796166900;
    end.end_unix_s = 1796166960;
    jetrace::proto::StandingEntry a;
    a.slot = 1;
    a.name = "ann";
    a.finished = true;
    end.standings = {a};
    end.racers = {{0, "bob", true}, {1, "ann", false}};
    const auto j = js::results_json(end, "ring", 3);
    EXPECT_EQ(j["end_reason"], "drained");
    EXPECT_EQ(j["aborted"], true);
    EXPECT_EQ(j["start_utc"], "2026-12-01T23:15:00Z");
    EXPECT_EQ(j["end_utc"], "2026-12-01T23:16:00Z");
    ASSERT_EQ(j["standings"].size(), 2u);
    EXPECT_EQ(j["standings"][0]["name"], "ann");
    EXPECT_EQ(j["standings"][1]["name"], "bob");
    EXPECT_EQ(j["standings"][1]["dropped"], true);
    EXPECT_EQ(j["standings"][1]["finished"], false);
    end.start_unix_s = 0;
    end.reason = jetrace::replay::EndReason::finished;
    const auto k = js::results_json(end, "ring", 3);
    EXPECT_TRUE(k["start_utc"].is_null());
    EXPECT_EQ(k["aborted"], false);
}

TEST(HostFiles, NonceTableRoundTripsAndRefusesCorruption) {
    TempDir dir;
    const std::string path = (dir.path / "nonces").string();
    std::vector<jetrace::auth::SpentNonce> in(2), out;
    in[0].nonce.fill(0xab);
    in[0].expires_unix_s = 1796166900;
    in[1].nonce.fill(0x01);
    in[1].expires_unix_s = 5;
    std::string error;
    ASSERT_TRUE(js::load_nonce_file(path, out, error)) << error;  // missing: nothing spent
    EXPECT_TRUE(out.empty());
    ASSERT_TRUE(js::save_nonce_file(path, in, error)) << error;
    ASSERT_TRUE(js::load_nonce_file(path, out, error)) << error;
    EXPECT_EQ(out, in);
    for (const char* bad : {"", "jetrace-nonces 2\n", "jetrace-nonces 1\nzz 5\n", "jetrace-nonces 1\n0101 5\n",
                            "jetrace-nonces 1\n01010101010101010101010101010101 5 6\n"}) {
        std::ofstream(path, std::ios::trunc) << bad;
        EXPECT_FALSE(js::load_nonce_file(path, out, error)) << bad;
        EXPECT_NE(error.find("is corrupt"), std::string::npos) << error;
    }
}
