// A live race for tests: the real RaceServer on real ENet on 127.0.0.1 (port
// chosen at run time), honest AI bots (RaceClient) and raw clients that send
// whatever bytes a test crafts, all in one process on a virtual clock that
// runs faster than real time (1 ms per step).
#pragma once

#include "jetrace/builtin_tracks.hpp"
#include "jetrace/client/race_client.hpp"
#include "jetrace/driver_ai.hpp"
#include "jetrace/offline_race.hpp"
#include "jetrace/server/race_server.hpp"

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

namespace jetrace::test {

/// A client that speaks raw bytes: it sends what the test gives it and
/// remembers what the server said.
class RawClient {
public:
    explicit RawClient(std::uint16_t port, std::uint32_t timeout_ms = 5000) {
        transport_ = net::connect_enet("127.0.0.1", port, timeout_ms, error);
    }
    void service(std::uint64_t now_ms) {
        if (!transport_) return;
        events_.clear();
        transport_->service(now_ms, events_);
        for (const net::Event& e : events_) {
            if (e.type == net::Event::Type::connected) connected = true;
            if (e.type == net::Event::Type::disconnected) disconnected = true;
            if (e.type != net::Event::Type::received) continue;
            proto::Message m;
            std::string why;
            if (!proto::decode(e.data, m, why)) continue;
            if (const auto* w = std::get_if<proto::Welcome>(&m)) welcome = *w;
            if (const auto* r = std::get_if<proto::Refuse>(&m)) refuse = r->reason;
            if (const auto* g = std::get_if<proto::Goodbye>(&m)) goodbye = g->reason;
            if (const auto* s = std::get_if<proto::Snapshot>(&m)) {
                ++snapshots;
                if (s->phase == proto::RacePhase::countdown || s->phase == proto::RacePhase::racing)
                    server_tick = s->server_tick;
            }
        }
        transport_->flush();
    }
    bool send(std::span<const std::uint8_t> bytes, net::Channel channel = net::Channel::reliable) {
        return transport_ && transport_->send(0, channel, bytes);
    }
    bool send(const proto::Message& m, net::Channel channel = net::Channel::reliable) {
        return send(proto::encode(m), channel);
    }
    /// Stops answering (never serviced again), like a machine that vanished.
    void vanish() { vanished = true; }

    std::string error;
    bool connected = false;
    bool disconnected = false;
    bool vanished = false;
    std::optional<proto::Welcome> welcome;
    std::string refuse;
    std::string goodbye;
    std::uint64_t snapshots = 0;
    /// Newest server tick of a countdown or racing snapshot.
    std::uint32_t server_tick = 0;

private:
    std::unique_ptr<net::Transport> transport_;
    std::vector<net::Event> events_;
};

struct LiveRaceOptions {
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
    /// After the first car finishes, the others have this long (unit: s).
    double finish_window_s = 120;
    /// Virtual time a connection may stay silent before its Hello (unit: s).
    double hello_timeout_s = 5.0;
    std::uint64_t skill_seed = 11;
    /// Network conditions on the sending side of the server and of every bot
    /// (bot i: seed + 1000 + i); null: none.
    const net::Conditions* conditions = nullptr;
    /// Wraps a bot's transport (e.g. to make it misbehave); null: as is.
    std::function<std::unique_ptr<net::Transport>(int bot, std::unique_ptr<net::Transport>)> wrap;
};

class LiveRace {
public:
    explicit LiveRace(const LiveRaceOptions& o) : options_(o) {
        Track track;
        make_builtin_track("ring", track);
        scene_ = std::make_unique<Scene>(Scene::make(std::move(track), PhysicsSettings{}));
        replay_path_ = (std::filesystem::temp_directory_path() /
                        ("jetrace_live_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++) + ".replay"))
                           .string();
        server::ServerConfig cfg;
        cfg.laps = o.laps;
        cfg.max_players = o.max_players > 0 ? o.max_players : o.bots;
        cfg.min_players = o.min_players > 0 ? o.min_players : o.bots;
        cfg.races = o.races;
        cfg.countdown_s = 1.0;
        cfg.results_pause_s = 1.0;
        cfg.finish_window_s = o.finish_window_s;
        cfg.hello_timeout_s = o.hello_timeout_s;
        cfg.record_path = replay_path_;
        net::ServerConfig ncfg;
        ncfg.bind = "127.0.0.1";
        ncfg.port = 0;
        ncfg.max_connections = static_cast<std::size_t>(cfg.max_players) + o.spare_connections;
        ncfg.timeout_ms = o.server_timeout_ms;
        server_net_ = net::listen_enet(ncfg, error);
        if (!server_net_) return;
        port = server_net_->local_port();
        if (o.conditions) server_net_ = net::condition(std::move(server_net_), *o.conditions);
        server_ = std::make_unique<server::RaceServer>(cfg, *scene_, *server_net_);
        server_->on_race_end = [this](const server::RaceEnd& e) {
            ends.push_back(e);
            end_worlds.push_back(server_->world());
        };
        skills_ = skills_for(o.bots, o.skill_seed);
        for (int i = 0; i < o.bots; ++i) {
            auto t = net::connect_enet("127.0.0.1", port, 5000, error);
            if (!t) return;
            if (o.conditions) {
                net::Conditions c = *o.conditions;
                c.seed = o.conditions->seed + 1000 + static_cast<std::uint64_t>(i);
                t = net::condition(std::move(t), c);
            }
            if (o.wrap) t = o.wrap(i, std::move(t));
            client::ClientConfig cc;
            cc.name = "bot" + std::to_string(i);
            bots_.push_back(std::make_unique<client::RaceClient>(cc, *scene_, *t));
            bot_nets_.push_back(std::move(t));
        }
        frozen_.assign(bots_.size(), false);
        ok_ = true;
    }
    ~LiveRace() { std::filesystem::remove(replay_path_); }

    bool ok() const { return ok_; }
    server::RaceServer& server() { return *server_; }
    client::RaceClient& bot(int i) { return *bots_[static_cast<std::size_t>(i)]; }
    int bots() const { return static_cast<int>(bots_.size()); }
    std::uint64_t now_us() const { return now_us_; }
    const Scene& scene() const { return *scene_; }

    RawClient& add_raw(std::uint32_t timeout_ms = 5000) {
        raws_.push_back(std::make_unique<RawClient>(port, timeout_ms));
        return *raws_.back();
    }
    /// Bot i stops running (no updates: its ENet host falls silent).
    void freeze_bot(int i) { frozen_[static_cast<std::size_t>(i)] = true; }

    /// One virtual millisecond: the server, every bot and raw client.
    void step() {
        now_us_ += 1000;
        server_->update(now_us_);
        for (std::size_t i = 0; i < bots_.size(); ++i) {
            if (frozen_[i]) continue;
            const DriverSkill skill = skills_[i];
            bots_[i]->update(now_us_, [&](const Scene& sc, const WorldState& w, int slot) { return drive(sc, w, slot, skill); });
        }
        for (auto& r : raws_) {
            if (!r->vanished) r->service(now_us_ / 1000);
        }
        if (now_us_ % 5000 == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
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

    /// Whether bot i finished according to the results it received.
    bool finished(int i) const {
        const auto& c = *bots_[static_cast<std::size_t>(i)];
        for (const auto& s : c.results().standings) {
            if (s.slot == c.slot()) return s.finished;
        }
        return false;
    }
    /// The final state hash of re-simulating the recorded replay (nullopt: unreadable).
    std::optional<std::uint64_t> replay_hash() const {
        Replay replay;
        std::string why;
        if (!read_replay(replay_path_, replay, why) ||
            !check_replay(*scene_, replay, physics_fingerprint(scene_->physics), why))
            return std::nullopt;
        return state_hash(run_replay(*scene_, replay));
    }

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

    LiveRaceOptions options_;
    bool ok_ = false;
    std::unique_ptr<Scene> scene_;
    std::string replay_path_;
    std::unique_ptr<net::Transport> server_net_;
    std::unique_ptr<server::RaceServer> server_;
    std::vector<DriverSkill> skills_;
    std::vector<std::unique_ptr<net::Transport>> bot_nets_;
    std::vector<std::unique_ptr<client::RaceClient>> bots_;
    std::vector<bool> frozen_;
    std::vector<std::unique_ptr<RawClient>> raws_;
    std::uint64_t now_us_ = 0;
};

}  // namespace jetrace::test
