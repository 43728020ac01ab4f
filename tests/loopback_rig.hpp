// Shared by the live-server tests of reconnects and private races: an
// in-process RaceServer over real ENet on 127.0.0.1 with a virtual clock,
// AI bots whose connection can be cut (Severable), and raw handshakes that
// return the server's answer to a hand-made Hello.
#pragma once

#include "jetrace/builtin_tracks.hpp"
#include "jetrace/client/race_client.hpp"
#include "jetrace/driver_ai.hpp"
#include "jetrace/offline_race.hpp"
#include "jetrace/server/race_server.hpp"

#include <gtest/gtest.h>
#include <spdlog/cfg/env.h>

#include <chrono>
#include <functional>
#include <memory>
#include <thread>
#include <variant>

namespace rig {

using namespace jetrace;

/// A fixed wall clock for connect tokens (unit: s since 1970).
inline constexpr std::int64_t kUnixNow = 1'700'000'000;

/// A client transport whose connection can be cut: sever() destroys the
/// ENet connection without a Goodbye (the server sees a disconnect at once,
/// as when a game crashes) and reports `disconnected` to its owner.
class Severable final : public net::Transport {
public:
    explicit Severable(std::unique_ptr<net::Transport> inner) : inner_(std::move(inner)) {}
    void sever() {
        if (!inner_) return;
        last_totals_ = inner_->totals();
        inner_.reset();
    }
    bool severed() const { return !inner_; }
    void service(std::uint64_t now_ms, std::vector<net::Event>& events) override {
        if (inner_) return inner_->service(now_ms, events);
        if (!announced_) events.push_back({net::Event::Type::disconnected, 0, net::Channel::reliable, {}});
        announced_ = true;
    }
    bool send(net::PeerId p, net::Channel c, std::span<const std::uint8_t> d) override {
        return inner_ && inner_->send(p, c, d);
    }
    void disconnect(net::PeerId p) override {
        if (inner_) inner_->disconnect(p);
    }
    void flush() override {
        if (inner_) inner_->flush();
    }
    net::PeerStats peer_stats(net::PeerId p) const override { return inner_ ? inner_->peer_stats(p) : net::PeerStats{}; }
    net::Totals totals() const override { return inner_ ? inner_->totals() : last_totals_; }
    std::uint16_t local_port() const override { return inner_ ? inner_->local_port() : 0; }

private:
    std::unique_ptr<net::Transport> inner_;
    net::Totals last_totals_;
    bool announced_ = false;
};

/// An AI driver on its own connection; `link` is its current one.
struct Bot {
    std::unique_ptr<client::RaceClient> client;
    DriverSkill skill;
    Severable* link = nullptr;
};

struct Rig {
    Scene scene;
    std::unique_ptr<net::Transport> server_net;
    std::uint16_t port = 0;
    std::unique_ptr<server::RaceServer> server;
    std::vector<std::unique_ptr<Bot>> bots;
    std::uint64_t now_us = 0;
    /// What update() passes the server as the wall clock (-1: nothing).
    std::int64_t unix_s = kUnixNow;

    /// A 1-lap race on `ring` with short pauses, then the changes in `tweak`.
    explicit Rig(const std::function<void(server::ServerConfig&)>& tweak = {}) : scene(make_scene()) {
        spdlog::cfg::load_env_levels();  // SPDLOG_LEVEL=debug for the details
        server::ServerConfig cfg;
        cfg.laps = 1;
        cfg.max_players = 4;
        cfg.min_players = 2;
        cfg.races = 1;
        cfg.countdown_s = 1.0;
        cfg.results_pause_s = 1.0;
        if (tweak) tweak(cfg);
        net::ServerConfig ncfg;
        ncfg.bind = "127.0.0.1";
        ncfg.port = 0;
        ncfg.max_connections = 16;
        std::string error;
        server_net = net::listen_enet(ncfg, error);
        if (!server_net) throw std::runtime_error(error);
        port = server_net->local_port();
        server = std::make_unique<server::RaceServer>(cfg, scene, *server_net);
    }

    static Scene make_scene() {
        Track track;
        make_builtin_track("ring", track);
        return Scene::make(std::move(track), PhysicsSettings{});
    }

    std::unique_ptr<net::Transport> connect() const {
        std::string error;
        auto t = net::connect_enet("127.0.0.1", port, 5000, error);
        EXPECT_TRUE(t) << error;
        return t;
    }

    /// A bot that reconnects through a fresh Severable connection.
    Bot& add_bot(client::ClientConfig cc) {
        auto bot = std::make_unique<Bot>();
        bot->skill = skills_for(8, 11)[bots.size() % 8];
        Bot* b = bot.get();
        bot->client = std::make_unique<client::RaceClient>(cc, scene, [this, b]() -> std::unique_ptr<net::Transport> {
            auto inner = connect();
            if (!inner) return nullptr;
            auto s = std::make_unique<Severable>(std::move(inner));
            b->link = s.get();
            return s;
        });
        bots.push_back(std::move(bot));
        return *bots.back();
    }
    Bot& add_bot(const std::string& name) {
        client::ClientConfig cc;
        cc.name = name;
        return add_bot(cc);
    }

    /// One virtual millisecond: the server, then every bot not in `paused`.
    void step(const std::vector<const Bot*>& paused = {}) {
        now_us += 1000;
        if (unix_s >= 0) server->update(now_us, unix_s);
        else server->update(now_us);
        for (auto& b : bots) {
            if (std::find(paused.begin(), paused.end(), b.get()) != paused.end()) continue;
            const DriverSkill skill = b->skill;
            b->client->update(now_us, [skill](const Scene& sc, const WorldState& w, int slot) {
                return drive(sc, w, slot, skill);
            });
        }
        // Give ENet real time to move the datagrams.
        if (now_us % 5000 == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
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

    /// Sends `hello` on a new connection and returns the server's answer
    /// (Welcome or Refuse; monostate if none within 3 virtual seconds). The
    /// connection is then handed to `*keep` if given (nobody services it),
    /// else closed with a Goodbye.
    std::variant<std::monostate, proto::Welcome, proto::Refuse> handshake(
        const proto::Hello& hello, const std::vector<const Bot*>& paused = {},
        std::unique_ptr<net::Transport>* keep = nullptr) {
        auto t = connect();
        std::variant<std::monostate, proto::Welcome, proto::Refuse> answer;
        if (!t) return answer;
        std::vector<net::Event> events;
        run_until(
            [&] {
                events.clear();
                t->service(now_us / 1000, events);
                for (const net::Event& e : events) {
                    proto::Message m;
                    std::string error;
                    if (e.type == net::Event::Type::connected) {
                        t->send(0, net::Channel::reliable, proto::encode(hello));
                    } else if (e.type == net::Event::Type::received && proto::decode(e.data, m, error)) {
                        if (auto* w = std::get_if<proto::Welcome>(&m)) answer = *w;
                        if (auto* r = std::get_if<proto::Refuse>(&m)) answer = *r;
                    }
                }
                t->flush();
                return answer.index() != 0;
            },
            3000, paused);
        if (keep) {
            *keep = std::move(t);
            return answer;
        }
        t->send(0, net::Channel::reliable, proto::encode(proto::Goodbye{"test done"}));
        t->disconnect(0);
        t->flush();
        return answer;
    }
};

/// The reason of a Refuse answer, or what came instead.
inline std::string refusal(const std::variant<std::monostate, proto::Welcome, proto::Refuse>& a) {
    if (const auto* r = std::get_if<proto::Refuse>(&a)) return r->reason;
    return a.index() == 1 ? "(welcomed)" : "(no answer)";
}

}  // namespace rig
