// jetrace-view's units: page messages (every field and range checked),
// static file names (nothing outside the page's files and three.js), and a
// recorded race seeked in every order matching its straight re-simulation.
#include "page_messages.hpp"
#include "playback.hpp"
#include "static_files.hpp"
#include "world_json.hpp"

#include "jetrace/builtin_tracks.hpp"
#include "jetrace/offline_race.hpp"
#include "jetrace/race.hpp"
#include "jetrace/replay/scene_for.hpp"
#include "jetrace/replay/writer.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <random>

namespace jetrace::view {
namespace {

const PageLimits kLimits{10, 500};

bool parses(const std::string& text, PageMessage& m) {
    std::string error;
    return parse_page_message(text, kLimits, m, error);
}

TEST(PageMessages, AcceptsEachKind) {
    PageMessage m;
    ASSERT_TRUE(parses(R"({"type":"play"})", m));
    EXPECT_TRUE(std::get<PlayMessage>(m).playing);
    ASSERT_TRUE(parses(R"({"type":"pause"})", m));
    EXPECT_FALSE(std::get<PlayMessage>(m).playing);
    ASSERT_TRUE(parses(R"({"type":"speed","value":0.25})", m));
    EXPECT_EQ(std::get<SpeedMessage>(m).speed, 0.25);
    ASSERT_TRUE(parses(R"({"value":8,"type":"speed"})", m));
    EXPECT_EQ(std::get<SpeedMessage>(m).speed, 8.0);
    ASSERT_TRUE(parses(R"({"type":"seek","tick":10})", m));
    EXPECT_EQ(std::get<SeekMessage>(m).tick, 10u);
    ASSERT_TRUE(parses(R"({"type":"seek","tick":500})", m));
    EXPECT_EQ(std::get<SeekMessage>(m).tick, 500u);
}

TEST(PageMessages, RejectsEverythingElse) {
    const char* bad[] = {
        "", "null", "[]", "\"play\"", "{", R"({"type":"play"} x)", R"({"type":1})", R"({"type":"stop"})",
        R"({"type":"play","extra":1})", R"({"type":"speed"})", R"({"type":"speed","value":"1"})",
        R"({"type":"speed","value":0.2})", R"({"type":"speed","value":8.01})", R"({"type":"speed","value":1e999})",
        R"({"type":"speed","value":-1e999})", R"({"type":"speed","value":NaN})", R"({"type":"speed","value":null})",
        R"({"type":"seek","tick":9})", R"({"type":"seek","tick":501})", R"({"type":"seek","tick":-1})",
        R"({"type":"seek","tick":10.5})", R"({"type":"seek","tick":1e3})", R"({"type":"seek","tick":18446744073709551616})",
        R"({"type":"seek","tick":[10]})", R"({"type":"seek","tick":10,"tick2":3})", R"({"type":"seek"})",
    };
    for (const char* text : bad) {
        PageMessage m;
        EXPECT_FALSE(parses(text, m)) << text;
    }
    PageMessage m;
    EXPECT_FALSE(parses(R"({"type":"play"})" + std::string(kMaxPageMessageBytes, ' '), m));
}

TEST(StaticFiles, ServesOnlyThePageAndThree) {
    const std::string web = JETRACE_SOURCE_DIR "/client/view/web", modules = JETRACE_SOURCE_DIR "/node_modules";
    ASSERT_TRUE(resolve_static("/", web, modules));
    EXPECT_EQ(resolve_static("/app.js?x=1", web, modules)->content_type, "text/javascript; charset=utf-8");
    EXPECT_TRUE(resolve_static("/three/build/three.module.js", web, modules));
    for (const char* bad : {"", "x", "/nosuch.js", "/../CMakeLists.txt", "/three/../three/package.json",
                            "/three/build/../../puppeteer-core/package.json", "/three/package.json", "/.git",
                            "/three/build/", "/three//build/three.module.js", "/%2e%2e/x.js", "/three/build/.x.js"}) {
        EXPECT_FALSE(resolve_static(bad, web, modules)) << bad;
    }
}

/// A recorded offline race on ring, written to a temporary file.
class RecordedRace : public ::testing::Test {
protected:
    void SetUp() override {
        path_ = (std::filesystem::temp_directory_path() / ("test_view_" + std::to_string(::getpid()) + ".jtr")).string();
        Track track;
        ASSERT_TRUE(make_builtin_track("ring", track));
        scene_ = std::make_unique<Scene>(Scene::make(std::move(track), PhysicsSettings{}));
        start_ = start_race(*scene_, 3, 3);
        WorldState s = start_;
        replay::Writer w;
        replay::Recorder rec(w);
        ASSERT_TRUE(w.open(path_, replay::header_for(*scene_, s)));
        StepScratch scratch;
        run_ai(*scene_, s, skills_for(3, 7), kTicks, false, scratch, &rec);
        ASSERT_TRUE(w.finish(replay::trailer_for(*scene_, s, replay::EndReason::time_limit)));
    }
    void TearDown() override { std::filesystem::remove(path_); }

    /// The world at `tick`, stepped straight from the start.
    std::uint64_t straight_hash(std::uint32_t tick) {
        WorldState s = start_;
        StepScratch scratch;
        run_ai(*scene_, s, skills_for(3, 7), tick, false, scratch, nullptr);
        return state_hash(s);
    }

    static constexpr std::uint32_t kTicks = 4000;  // about 33 s: two laps of ring and more
    std::string path_;
    std::unique_ptr<Scene> scene_;
    WorldState start_;
};

TEST_F(RecordedRace, SeeksInAnyOrderMatchTheStraightRun) {
    ReplayPlayer p;
    std::string error;
    PlayerLimits limits;
    limits.keep_every_ticks = 100;
    ASSERT_TRUE(p.load(path_, replay::scene_for(replay::load_builtin), limits, error)) << error;
    EXPECT_TRUE(p.complete());
    EXPECT_EQ(p.last_tick(), kTicks);
    const std::uint64_t seed = std::random_device{}();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    std::mt19937_64 rng(seed);
    Playback pb(p, {&p});
    for (int i = 0; i < 25; ++i) {
        const auto tick = static_cast<std::uint32_t>(rng() % (kTicks + 1));
        pb.seek(tick);
        ASSERT_EQ(pb.tick(), tick);
        EXPECT_EQ(state_hash(pb.main_state()), straight_hash(tick)) << "tick " << tick << " seed " << seed;
        EXPECT_EQ(state_hash(pb.ghost_state(0)), state_hash(pb.main_state()));
    }
    pb.seek(kTicks + 100);
    EXPECT_EQ(pb.tick(), kTicks);
}

TEST_F(RecordedRace, PlaysAtItsSpeedAndStopsAtTheEnd) {
    ReplayPlayer p;
    std::string error;
    ASSERT_TRUE(p.load(path_, replay::scene_for(replay::load_builtin), {}, error)) << error;
    Playback pb(p, {});
    pb.set_speed(2.0);
    pb.set_playing(true);
    EXPECT_TRUE(pb.advance(0.5));  // 0.5 s at 2x: one second of ticks
    EXPECT_EQ(pb.tick(), static_cast<std::uint32_t>(scene_->physics.tick_rate_hz));
    EXPECT_EQ(state_hash(pb.main_state()), straight_hash(pb.tick()));
    pb.advance(1000.0);
    EXPECT_EQ(pb.tick(), kTicks);
    EXPECT_FALSE(pb.playing());
    const std::string frame = frame_json(pb);
    EXPECT_NE(frame.find("\"standings\""), std::string::npos);
    EXPECT_NE(frame.find("\"best_lap_s\""), std::string::npos);
}

TEST_F(RecordedRace, TimesLapsAndGaps) {
    ReplayPlayer p;
    std::string error;
    ASSERT_TRUE(p.load(path_, replay::scene_for(replay::load_builtin), {}, error)) << error;
    const RaceTiming& t = p.timing();
    const int rate = scene_->physics.tick_rate_hz;
    const auto gates = scene_->track.checkpoints.size();
    WorldState end;
    StepScratch scratch;
    p.seek(end, scratch, p.last_tick());
    const auto order = standings(scene_->track, end.cars, end.start_tick, rate);
    const int leader = order.front().slot;
    EXPECT_GE(t.passes(leader, p.last_tick()), 2 * gates + 1);
    const auto best = t.best_lap_s(leader, p.last_tick(), rate);
    ASSERT_TRUE(best);
    EXPECT_GT(*best, 1.0);
    EXPECT_LT(*best, static_cast<double>(kTicks) / rate / 2);
    EXPECT_FALSE(t.best_lap_s(leader, p.first_tick(), rate));  // nothing known at the start
    EXPECT_FALSE(t.gap_s(leader, leader, p.last_tick(), rate));
    const auto gap = t.gap_s(order.back().slot, leader, p.last_tick(), rate);
    ASSERT_TRUE(gap);
    EXPECT_GE(*gap, 0.0);
}

TEST(ReplayNames, InvalidUtf8IsReplacedNotThrown) {
    const std::string path =
        (std::filesystem::temp_directory_path() / ("test_view_names_" + std::to_string(::getpid()) + ".jtr")).string();
    Track track;
    ASSERT_TRUE(make_builtin_track("ring", track));
    const Scene scene = Scene::make(std::move(track), PhysicsSettings{});
    WorldState s = start_race(scene, 2, 1);
    replay::Header h = replay::header_for(scene, s);
    h.names = {"ok", "\xff\xfe<b>"};
    replay::Writer w;
    replay::Recorder rec(w);
    ASSERT_TRUE(w.open(path, h));
    StepScratch scratch;
    run_ai(scene, s, skills_for(2, 1), 30, false, scratch, &rec);
    ASSERT_TRUE(w.finish(replay::trailer_for(scene, s, replay::EndReason::time_limit)));
    ReplayPlayer p;
    std::string error;
    ASSERT_TRUE(p.load(path, replay::scene_for(replay::load_builtin), {}, error)) << error;
    std::filesystem::remove(path);
    const Playback pb(p, {});
    std::string hello, frame;
    ASSERT_NO_THROW(hello = hello_json(pb));
    ASSERT_NO_THROW(frame = frame_json(pb));
    EXPECT_NE(hello.find("\"ok\""), std::string::npos);
    EXPECT_NE(hello.find("\xef\xbf\xbd"), std::string::npos);  // U+FFFD
    EXPECT_NE(frame.find("\xef\xbf\xbd"), std::string::npos);
}

TEST_F(RecordedRace, RefusesAnAlteredReplay) {
    auto bytes = std::filesystem::file_size(path_);
    std::FILE* f = std::fopen(path_.c_str(), "r+b");
    ASSERT_NE(f, nullptr);
    std::fseek(f, static_cast<long>(bytes / 2), SEEK_SET);
    std::fputc(0x5a, f);
    std::fclose(f);
    ReplayPlayer p;
    std::string error;
    EXPECT_FALSE(p.load(path_, replay::scene_for(replay::load_builtin), {}, error));
    EXPECT_FALSE(error.empty());
}

}  // namespace
}  // namespace jetrace::view
