// A live race for tests: the real RaceServer on real ENet on 127.0.0.1 (port
// chosen at run time), AI bots (RaceClient) and raw clients that send
// whatever bytes a test crafts (raw_client.hpp), all in one process on a
// virtual clock that runs faster than real time (1 ms per step).
//
// Bots come two ways: connected at the start over a fixed connection (with
// network conditions or a wrapper, no reconnects), or added later with
// add_bot(), over a connection the test may cut (severable.hpp) and that the
// client replaces by reconnecting.
#pragma once

#include "input_audit.hpp"
#include "jetrace/ai/driver_ai.hpp"
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/ai/pilot.hpp"
#include "jetrace/client/race_client.hpp"
#include "jetrace/replay/diff.hpp"
#include "jetrace/server/race_server.hpp"
#include "jetrace/server/replay_recorder.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"
#include "raw_client.hpp"
#include "severable.hpp"

#include <gtest/gtest.h>
#include <spdlog/cfg/env.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

namespace jetrace::test {

/// A fixed wall clock for connect tokens (unit: s since 1970).
inline constexpr std::int64_t kUnixNow = 1'700'000'000;

struct LiveRaceOptions {
    /// Bots connected at the start (unit: bots); add_bot() adds more later.
    int bots = 4;
    int laps = 1;
    /// Races before the server is done (unit: races).
    int races = 1;
    /// 0: as many as bots (unit: players).
    int max_players = 0;
    /// 0: as many as bots (unit: players).
    int min_players = 0;
    /// ENet connections beyond max_players, for clients to be refused (unit: connections).
    std::size_t spare_connections = 8;
    /// The server's ENet timeout (unit: ms).
    std::uint32_t server_timeout_ms = 5000;
    /// net::ServerConfig::max_pending_per_address (0: no cap; unit: connections).
    std::size_t max_pending_per_address = 0;
    /// After the first car finishes, the others have this long (unit: s).
    double finish_window_s = 120;
    /// Virtual time a connection may stay silent before its Hello (unit: s).
    double hello_timeout_s = 5.0;
    /// Bot k (in the order they join) drives with skills_for(k + 1, skill_seed)[k].
    std::uint64_t skill_seed = 11;
    /// Network conditions on the sending side of the server and of every bot
    /// connected at the start (bot i: seed + 1000 + i); null: none.
    const net::Conditions* conditions = nullptr;
    /// Wraps the transport of a bot connected at the start (e.g. to make it misbehave); null: as is.
    std::function<std::unique_ptr<net::Transport>(int bot, std::unique_ptr<net::Transport>)> wrap;
    /// Whether the server records its races (see LiveRace::replay_hash()).
    bool record = true;
    /// The wall clock the server is given at the start (see LiveRace::unix_s).
    std::int64_t unix_s = -1;
    /// Applies SPDLOG_LEVEL (SPDLOG_LEVEL=debug for the details).
    bool log_levels_from_env = false;
    /// The track raced on (null: the built-in ring).
    const Track* track = nullptr;
    /// ClientConfig::input_delay_ticks of the bots connected at the start (unit: ticks).
    std::uint32_t input_delay_ticks = 0;
    /// Last changes to the server's configuration (e.g. a connect key).
    std::function<void(server::ServerConfig&)> tweak;
    /// Wraps or joins the server's ENet transport (e.g. with a WebSocket
    /// one: net::combine); null: as is.
    std::function<std::unique_ptr<net::Transport>(std::unique_ptr<net::Transport>)> server_wrap;
};

/// A server that waits for the players a test brings (add_bot(), handshake()):
/// no bots at the start, 4 slots, the countdown from 2 players, the server's
/// own finish window, 16 ENet connections, the wall clock at kUnixNow (for
/// connect tokens), SPDLOG_LEVEL applied, no replay; then the changes in `tweak`.
inline LiveRaceOptions lobby_options(std::function<void(server::ServerConfig&)> tweak = {}) {
    LiveRaceOptions o;
    o.bots = 0;
    o.max_players = 4;
    o.min_players = 2;
    o.spare_connections = 12;
    o.finish_window_s = server::ServerConfig{}.finish_window_s;
    o.record = false;
    o.unix_s = kUnixNow;
    o.log_levels_from_env = true;
    o.tweak = std::move(tweak);
    return o;
}

/// An AI driver on its own connection.
struct Bot {
    /// The connection of a bot connected at the start, which its client uses (no reconnects).
    std::unique_ptr<net::Transport> net;
    std::unique_ptr<client::RaceClient> client;
    Pilot pilot;  // its AI: skill, course of the scene the client races on, held input
    /// The current connection of a bot from add_bot(), which the test may cut.
    Severable* link = nullptr;
    /// Not updated any more: its ENet host falls silent (LiveRace::freeze_bot()).
    bool frozen = false;
    /// What a bot connected at the start sent, seen before any wrapper (null for add_bot()).
    SentInputs* sent = nullptr;
};

class LiveRace {
public:
    explicit LiveRace(const LiveRaceOptions& o) : unix_s(o.unix_s), options_(o) {
        if (o.log_levels_from_env) spdlog::cfg::load_env_levels();
        Track track;
        if (o.track) track = *o.track;
        else make_builtin_track("ring", track);
        scene_ = std::make_unique<Scene>(Scene::make(std::move(track), PhysicsSettings{}));
        server::ServerConfig cfg;
        cfg.laps = o.laps;
        cfg.max_players = o.max_players > 0 ? o.max_players : o.bots;
        cfg.min_players = o.min_players > 0 ? o.min_players : o.bots;
        cfg.races = o.races;
        cfg.countdown_s = 1.0;
        cfg.results_pause_s = 1.0;
        cfg.finish_window_s = o.finish_window_s;
        cfg.hello_timeout_s = o.hello_timeout_s;
        if (o.record) {
            const std::string name =
                "jetrace_live_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++) + ".replay";
            replay_path_ = (std::filesystem::temp_directory_path() / name).string();
            recorder_ = std::make_unique<server::ReplayRecorder>(server::RecorderConfig{replay_path_, {}});
        }
        net::ServerConfig ncfg;
        ncfg.bind = "127.0.0.1";
        ncfg.port = 0;
        ncfg.max_connections = static_cast<std::size_t>(cfg.max_players) + o.spare_connections;
        ncfg.timeout_ms = o.server_timeout_ms;
        ncfg.max_pending_per_address = o.max_pending_per_address;
        if (o.tweak) o.tweak(cfg);
        server_net_ = net::listen_enet(ncfg, error);
        if (!server_net_) return;
        port = server_net_->local_port();
        if (o.conditions) server_net_ = net::condition(std::move(server_net_), *o.conditions);
        if (o.server_wrap) server_net_ = o.server_wrap(std::move(server_net_));
        if (!server_net_) return;
        server_ = std::make_unique<server::RaceServer>(cfg, *scene_, *server_net_);
        applied_ = std::make_unique<AppliedInputs>(recorder_.get());
        server_->observer = applied_.get();
        server_->on_race_end = [this](const server::RaceEnd& e) {
            ends.push_back(e);
            end_worlds.push_back(server_->world());
        };
        for (int i = 0; i < o.bots; ++i) {
            auto t = connect(5000, error);
            if (!t) return;
            if (o.conditions) {
                net::Conditions c = *o.conditions;
                c.seed = o.conditions->seed + 1000 + static_cast<std::uint64_t>(i);
                t = net::condition(std::move(t), c);
            }
            if (o.wrap) t = o.wrap(i, std::move(t));
            auto sent = std::make_unique<SentInputs>(std::move(t));
            client::ClientConfig cc;
            cc.name = "bot" + std::to_string(i);
            cc.input_delay_ticks = o.input_delay_ticks;
            Bot& b = new_bot();
            b.sent = sent.get();
            t = std::move(sent);
            b.net = std::move(t);
            b.client = std::make_unique<client::RaceClient>(cc, *scene_, *b.net);
        }
        ok_ = true;
    }
    ~LiveRace() {
        if (!replay_path_.empty()) std::filesystem::remove(replay_path_);
    }
    LiveRace(const LiveRace&) = delete;
    LiveRace& operator=(const LiveRace&) = delete;

    bool ok() const { return ok_; }
    server::RaceServer& server() { return *server_; }
    const server::RaceServer& server() const { return *server_; }
    Bot& bot(int i) { return *bots_[static_cast<std::size_t>(i)]; }
    int bots() const { return static_cast<int>(bots_.size()); }
    std::uint64_t now_us() const { return now_us_; }
    const Scene& scene() const { return *scene_; }

    /// A new connection to the server (null and `why` if it cannot be made).
    std::unique_ptr<net::Transport> connect(std::uint32_t timeout_ms, std::string& why) const {
        return net::connect_enet("127.0.0.1", port, timeout_ms, why);
    }

    /// A bot that connects now and after every drop, each time through a
    /// fresh Severable connection (its `link`).
    Bot& add_bot(const client::ClientConfig& cc) { return add_bot(cc, client::KnownScenes{scene_.get()}); }
    /// The same, knowing `scenes` (not necessarily the server's track), each
    /// connection passed through `wrap` if given.
    using Wrap = std::function<std::unique_ptr<net::Transport>(std::unique_ptr<net::Transport>)>;
    Bot& add_bot(const client::ClientConfig& cc, client::KnownScenes scenes, Wrap wrap = {}) {
        Bot& bot = new_bot();
        Bot* b = &bot;
        bot.client = std::make_unique<client::RaceClient>(
            cc, std::move(scenes), [this, b, wrap]() -> std::unique_ptr<net::Transport> {
                std::string why;
                auto inner = connect(5000, why);
                EXPECT_TRUE(inner) << why;
                if (!inner) return nullptr;
                auto s = std::make_unique<Severable>(std::move(inner));
                b->link = s.get();
                if (wrap) return wrap(std::move(s));
                return s;
            });
        return bot;
    }
    Bot& add_bot(const std::string& name) {
        client::ClientConfig cc;
        cc.name = name;
        return add_bot(cc);
    }

    /// A raw client, serviced on every step until it vanishes.
    RawClient& add_raw(std::uint32_t timeout_ms = 5000) {
        std::string why;
        auto t = connect(timeout_ms, why);
        raws_.push_back(std::make_unique<RawClient>(std::move(t), why));
        return *raws_.back();
    }
    /// The server process exits: the server and its transport are gone
    /// (ENet tells the peers still connected at once), step() runs the
    /// clients only; server() must not be called any more.
    void close_server() {
        server_.reset();
        server_net_.reset();
    }
    /// Bot i stops running (no updates: its ENet host falls silent).
    void freeze_bot(int i) { bots_[static_cast<std::size_t>(i)]->frozen = true; }

    /// One virtual millisecond: the server, every bot neither frozen nor in
    /// `paused`, every raw client.
    void step(const std::vector<const Bot*>& paused = {}) {
        now_us_ += 1000;
        if (!server_) {
        } else if (unix_s >= 0) {
            server_->update(now_us_, unix_s);
        } else {
            server_->update(now_us_);
        }
        for (const auto& b : bots_) {
            if (b->frozen || std::find(paused.begin(), paused.end(), b.get()) != paused.end()) continue;
            b->client->update(now_us_, std::ref(b->pilot));
        }
        for (auto& r : raws_) {
            if (!r->vanished) r->service(now_us_ / 1000);
        }
        // Give ENet real time to move the datagrams.
        if (now_us_ % 5000 == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }

    /// Steps until `done()` or `max_ms` virtual milliseconds; false on timeout.
    bool run_until(const std::function<bool()>& done, std::uint64_t max_ms,
                   const std::vector<const Bot*>& paused = {}) {
        for (std::uint64_t i = 0; i < max_ms; ++i) {
            if (done()) return true;
            step(paused);
        }
        return done();
    }

    /// Steps until the server is done (then lets the last messages arrive),
    /// calling `each` after every step. False if it did not end in time.
    bool run(const std::function<void()>& each = {}, double max_wall_s = 120) {
        const auto start = std::chrono::steady_clock::now();
        while (!server_->done()) {
            step();
            if (each) each();
            const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (wall > max_wall_s || now_us_ > 600'000'000u) return false;
        }
        for (int k = 0; k < 300; ++k) step();
        return true;
    }

    /// Sends `hello` on a new connection and returns the server's answer
    /// (monostate if none within 3 virtual seconds), stepping the race
    /// meanwhile. The connection is then handed to `*keep` if given (nobody
    /// services it), else closed with a Goodbye.
    Answer handshake(const proto::Hello& hello, const std::vector<const Bot*>& paused = {},
                     std::unique_ptr<RawClient>* keep = nullptr) {
        std::string why;
        auto raw = std::make_unique<RawClient>(connect(5000, why), why);
        EXPECT_TRUE(raw->ok()) << why;
        if (!raw->ok()) return {};
        raw->send_on_connect(hello);
        run_until(
            [&] {
                raw->service(now_us_ / 1000);
                return raw->answer().index() != 0;
            },
            3000, paused);
        const Answer answer = raw->answer();
        if (keep) *keep = std::move(raw);
        else raw->leave("test done");
        return answer;
    }

    /// Whether bot i finished according to the results it received.
    bool finished(int i) const {
        const auto& c = *bots_[static_cast<std::size_t>(i)]->client;
        for (const auto& s : c.results().standings) {
            if (s.slot == c.slot()) return s.finished;
        }
        return false;
    }
    /// Every slot's input of every tick the server stepped.
    const AppliedInputs& applied() const { return *applied_; }

    /// Checks that every bot connected at the start had its car stepped with
    /// exactly the inputs it sent (input_audit.hpp), and that it drove.
    void expect_cars_moved_by_their_own_bots() {
        for (const auto& b : bots_) {
            if (b->sent == nullptr) continue;
            const std::string who = "slot " + std::to_string(b->client->slot());
            const std::size_t own = expect_stepped_as_sent(*applied_, b->client->slot(), *b->sent, who);
            EXPECT_GT(own, applied_->by_tick.size() / 2) << who << ": stepped with its own inputs only this often";
        }
    }

    /// The final state hash of verifying the recorded replay (nullopt:
    /// unreadable, failing verification, or not recorded). A failure prints
    /// what jetrace-sim --diff REPLAY --rebuild would.
    std::optional<std::uint64_t> replay_hash() const {
        replay::FileSource src;
        std::string why;
        if (replay_path_.empty() || !src.open(replay_path_, why, replay::kMaxFileBytes)) return std::nullopt;
        const Scene* scene = scene_.get();
        const replay::Verdict v = replay::verify(src, [scene](const replay::Header&, std::string&) { return scene; });
        if (!v.ok) {
            std::fprintf(stderr, "replay verdict: %s\nas --diff --rebuild: %s\n", replay::to_json(v).c_str(),
                         replay::to_json(replay::diff_against_build(v)).c_str());
            return std::nullopt;
        }
        return v.state_hash;
    }

    /// What step() passes the server as the wall clock (unit: s since 1970; -1: nothing).
    std::int64_t unix_s = -1;
    std::uint16_t port = 0;
    std::string error;
    std::vector<server::RaceEnd> ends;
    /// The server's world at each race end.
    std::vector<WorldState> end_worlds;

private:
    static int& counter() {
        static int n = 0;
        return n;
    }
    /// A bot without a client yet, with the next skill.
    Bot& new_bot() {
        const int k = static_cast<int>(bots_.size());
        auto bot = std::make_unique<Bot>();
        bot->pilot = Pilot(skills_for(k + 1, options_.skill_seed)[static_cast<std::size_t>(k)]);
        bots_.push_back(std::move(bot));
        return *bots_.back();
    }

    LiveRaceOptions options_;
    bool ok_ = false;
    std::unique_ptr<Scene> scene_;
    std::string replay_path_;
    std::unique_ptr<net::Transport> server_net_;
    std::unique_ptr<server::ReplayRecorder> recorder_;  // before server_: outlives it
    std::unique_ptr<AppliedInputs> applied_;            // likewise
    std::unique_ptr<server::RaceServer> server_;
    std::vector<std::unique_ptr<Bot>> bots_;
    std::vector<std::unique_ptr<RawClient>> raws_;
    std::uint64_t now_us_ = 0;
};

}  // namespace jetrace::test
