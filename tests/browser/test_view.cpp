// jetrace-view's units: page messages (every field and range checked),
// static file names (nothing outside the page's files and three.js), and a
// recorded race seeked in every order matching its straight re-simulation.
#include "page_messages.hpp"
#include "playback.hpp"
#include "static_files.hpp"
#include "world_json.hpp"

#include "jetrace/ai/offline_race.hpp"
#include "jetrace/core/race.hpp"
#include "jetrace/replay/scene_for.hpp"
#include "jetrace/replay/writer.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

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

/// Records the race and the state hash after every step.
class HashingRecorder final : public StepObserver {
public:
    HashingRecorder(replay::Recorder& r, std::vector<std::uint64_t>& hashes) : r_(r), hashes_(hashes) {}
    void before_step(const WorldState& s, std::span<const Input> in) override { r_.before_step(s, in); }
    void after_step(const WorldState& s) override {
        r_.after_step(s);
        hashes_.push_back(state_hash(s));
    }

private:
    replay::Recorder& r_;
    std::vector<std::uint64_t>& hashes_;
};

/// A recorded offline race on ring (one for the suite: the sanitizer build
/// steps slowly), loaded once.
class RecordedRace : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        path_ = (std::filesystem::temp_directory_path() / ("test_view_" + std::to_string(::getpid()) + ".jtr")).string();
        Track track;
        ASSERT_TRUE(make_builtin_track("ring", track));
        scene_ = std::make_unique<Scene>(Scene::make(std::move(track), PhysicsSettings{}));
        WorldState s = start_race(*scene_, 3, 3);
        hashes_ = {state_hash(s)};
        replay::Writer w;
        replay::Recorder rec(w);
        HashingRecorder observer(rec, hashes_);
        ASSERT_TRUE(w.open(path_, replay::header_for(*scene_, s)));
        StepScratch scratch;
        run_ai(Course(*scene_), s, skills_for(3, 7), kTicks, false, scratch, &observer);
        ASSERT_TRUE(w.finish(replay::trailer_for(*scene_, s, replay::EndReason::time_limit)));
        player_ = std::make_unique<ReplayPlayer>();
        std::string error;
        PlayerLimits limits;
        limits.keep_every_ticks = 100;
        ASSERT_TRUE(player_->load(path_, replay::scene_for(load_builtin), limits, error)) << error;
    }
    static void TearDownTestSuite() {
        std::filesystem::remove(path_);
        player_.reset();
        scene_.reset();
    }

    static constexpr std::uint32_t kTicks = 3600;  // 30 s: two laps of ring and more
    static inline std::string path_;
    static inline std::unique_ptr<Scene> scene_;
    /// hashes_[t]: state_hash() of the recorded world at tick t.
    static inline std::vector<std::uint64_t> hashes_;
    static inline std::unique_ptr<ReplayPlayer> player_;
};

TEST_F(RecordedRace, SeeksInAnyOrderMatchTheRecording) {
    const ReplayPlayer& p = *player_;
    ASSERT_TRUE(p.complete());
    ASSERT_EQ(p.last_tick(), kTicks);
    ASSERT_EQ(hashes_.size(), kTicks + 1);
    const std::uint64_t seed = std::random_device{}();
    std::printf("seed %llu\n", static_cast<unsigned long long>(seed));
    std::mt19937_64 rng(seed);
    Playback pb(p, {&p});
    for (int i = 0; i < 40; ++i) {
        const auto tick = static_cast<std::uint32_t>(rng() % (kTicks + 1));
        pb.seek(tick);
        ASSERT_EQ(pb.tick(), tick);
        EXPECT_EQ(state_hash(pb.main_state()), hashes_[tick]) << "tick " << tick << " seed " << seed;
        EXPECT_EQ(state_hash(pb.ghost_state(0)), hashes_[tick]);
    }
    pb.seek(kTicks + 100);
    EXPECT_EQ(pb.tick(), kTicks);
}

TEST_F(RecordedRace, PlaysAtItsSpeedAndStopsAtTheEnd) {
    Playback pb(*player_, {});
    pb.set_speed(2.0);
    pb.set_playing(true);
    EXPECT_TRUE(pb.advance(0.5));  // 0.5 s at 2x: one second of ticks
    EXPECT_EQ(pb.tick(), static_cast<std::uint32_t>(scene_->physics.tick_rate_hz));
    EXPECT_EQ(state_hash(pb.main_state()), hashes_[pb.tick()]);
    pb.advance(1000.0);
    EXPECT_EQ(pb.tick(), kTicks);
    EXPECT_FALSE(pb.playing());
    const std::string frame = frame_json(pb);
    EXPECT_NE(frame.find("\"standings\""), std::string::npos);
    EXPECT_NE(frame.find("\"best_lap_s\""), std::string::npos);
}

TEST_F(RecordedRace, TimesLapsAndGaps) {
    const ReplayPlayer& p = *player_;
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
    run_ai(Course(scene), s, skills_for(2, 1), 30, false, scratch, &rec);
    ASSERT_TRUE(w.finish(replay::trailer_for(scene, s, replay::EndReason::time_limit)));
    ReplayPlayer p;
    std::string error;
    ASSERT_TRUE(p.load(path, replay::scene_for(load_builtin), {}, error)) << error;
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
    const std::string bad = path_ + ".bad";
    std::filesystem::copy_file(path_, bad, std::filesystem::copy_options::overwrite_existing);
    const auto bytes = std::filesystem::file_size(bad);
    std::FILE* f = std::fopen(bad.c_str(), "r+b");
    ASSERT_NE(f, nullptr);
    std::fseek(f, static_cast<long>(bytes / 2), SEEK_SET);
    const int was = std::fgetc(f);
    std::fseek(f, static_cast<long>(bytes / 2), SEEK_SET);
    std::fputc(was ^ 0xff, f);
    std::fclose(f);
    ReplayPlayer p;
    std::string error;
    EXPECT_FALSE(p.load(bad, replay::scene_for(load_builtin), {}, error));
    EXPECT_NE(error.find("corrupt"), std::string::npos) << error;
    std::filesystem::remove(bad);
}

}  // namespace
}  // namespace jetrace::view
