// Hostile clients against a live server (real ENet on 127.0.0.1, virtual
// clock) while an honest 4-bot race runs: junk bytes, malformed, oversized
// and out-of-range messages, messages out of order, an impostor, more
// players than slots, a silent connection, a speed hack, inputs far from the
// present, a client that vanishes. Each time the server stays up, drops or
// ignores the offender and says so in its log, and the honest race finishes
// with every car stepped by exactly the inputs its own client sent.
#include "support/forwarding_transport.hpp"
#include "support/live_race.hpp"
#include "support/log_capture.hpp"
#include "support/raw_client.hpp"
#include "support/test_seed.hpp"
#include "support/wire_craft.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace {

using jetrace::test::LiveRace;
using jetrace::test::LiveRaceOptions;
using jetrace::test::LogCapture;
using jetrace::test::RawClient;
namespace jp = jetrace::proto;
namespace fb = flatbuffers;
namespace w = jetrace::wire;

// The race every attack runs beside: 4 honest bots, 5 slots (one spare for
// an attacker), 1 lap of ring.
LiveRaceOptions honest_options() {
    LiveRaceOptions o;
    o.bots = 4;
    o.max_players = 5;
    return o;
}

// Every car was stepped with exactly what its own bot sent, and the race
// ended in the replay of those inputs: nothing the attacker did reached the
// simulation (support/input_audit.hpp says why not "the same race without it").
void expect_untouched(LiveRace& race) {
    ASSERT_EQ(race.ends.size(), 1u);
    EXPECT_EQ(race.replay_hash(), race.ends.front().state_hash) << "the race is not the replay of its inputs";
    race.expect_cars_moved_by_their_own_bots();
}

void expect_every_bot_finished(LiveRace& race, int bots) {
    for (int i = 0; i < bots; ++i) EXPECT_TRUE(race.finished(i)) << "bot " << i << " did not finish";
}

std::vector<std::uint8_t> bytes_of(const jp::Message& m) { return jp::encode(m); }

jp::InputBatch full_throttle(std::uint32_t first_tick, std::size_t count) {
    jp::InputBatch b;
    b.first_tick = first_tick;
    b.inputs.assign(count, jetrace::Input::clamped(15, 0, 0));
    return b;
}

// One attacker without a car: what it sends once connected, and what the
// server must answer (Goodbye or Refuse reason) and log.
struct Attack {
    std::string what;
    std::function<void(RawClient&)> act;
    std::string reason;  // the Goodbye or Refuse must contain it ("": none expected)
    RawClient* client = nullptr;
    bool done = false;
};

std::vector<Attack> junk_attacks(std::uint64_t seed) {
    std::vector<Attack> a;
    a.push_back({"random bytes", [seed](RawClient& c) {
                     std::mt19937_64 rng(seed);
                     std::vector<std::uint8_t> junk(1 + rng() % 512);
                     for (auto& b : junk) b = static_cast<std::uint8_t>(rng());
                     c.send(junk);
                 },
                 "malformed message"});
    a.push_back({"truncated hello", [](RawClient& c) {
                     auto b = bytes_of(jp::Hello{jp::kProtocolVersion, "trunc", {}, {}});
                     b.resize(b.size() / 2);
                     c.send(b);
                 },
                 "malformed message"});
    a.push_back({"oversized message", [](RawClient& c) {
                     auto b = bytes_of(jp::Hello{jp::kProtocolVersion, "big", {}, {}});
                     b.resize(9000, 0);
                     c.send(b);
                 },
                 "malformed message: message: larger than kMaxMessageBytes"});
    a.push_back({"300 tables sharing one (verifier table limit)", [](RawClient& c) {
                     fb::FlatBufferBuilder b;
                     const auto p = w::CreatePlayerInfo(b, 1, b.CreateString("p"), false);
                     const auto v = b.CreateVector(std::vector<fb::Offset<w::PlayerInfo>>(300, p));
                     c.send(jetrace::test::finish(b, w::CreateRaceStatus(b, w::RacePhase_Racing, 1, 0, 1, v), "JRST"));
                 },
                 "malformed message: message: malformed flatbuffer"});
    a.push_back({"root offset out of the buffer", [](RawClient& c) {
                     auto b = bytes_of(jp::Hello{jp::kProtocolVersion, "offset", {}, {}});
                     b[0] = 0xF0, b[1] = 0xFF, b[2] = 0xFF, b[3] = 0x7F;
                     c.send(b);
                 },
                 "malformed message"});
    a.push_back({"NaN finish time", [](RawClient& c) {
                     fb::FlatBufferBuilder b;
                     const auto e = w::CreateStandingEntry(b, 0, b.CreateString("x"), true, 1,
                                                           std::numeric_limits<double>::quiet_NaN());
                     const auto v = b.CreateVector(std::vector<fb::Offset<w::StandingEntry>>{e});
                     c.send(jetrace::test::finish(b, w::CreateResults(b, 1, v, 0), "JRES"));
                 },
                 "finish_time_s: not a finite time"});
    a.push_back({"name too long", [](RawClient& c) {
                     fb::FlatBufferBuilder b;
                     const auto h = w::CreateHello(b, jp::kProtocolVersion, b.CreateString(std::string(40, 'n')));
                     c.send(jetrace::test::envelope(b, w::Handshake_Hello, h.Union()));
                 },
                 "malformed message: Hello.name: too long"});
    a.push_back({"steer out of range", [](RawClient& c) {
                     c.send(jetrace::test::input_batch(
                                jetrace::test::Bits{}.ue(5, 14).u(0, 6).u(0, 1).u(0x1F0, 10).bytes()),
                            jetrace::net::Channel::unreliable);
                 },
                 "malformed message: InputBatch.inputs"});
    a.push_back({"input tick overflow", [](RawClient& c) {
                     c.send(jetrace::test::input_batch(
                                jetrace::test::Bits{}.ue(0xFFFFFFFFu, 14).u(1, 6).u(0, 1).u(0, 10).u(1, 1).bytes()),
                            jetrace::net::Channel::unreliable);
                 },
                 "malformed message: InputBatch.first_tick"});
    a.push_back({"inputs before hello",
                 [](RawClient& c) { c.send(full_throttle(0, 8), jetrace::net::Channel::unreliable); },
                 "protocol violation: inputs before hello"});
    a.push_back({"a server message",
                 [](RawClient& c) {
                     jp::Welcome wel;
                     wel.max_players = 1;
                     wel.track_name = "ring";
                     c.send(wel);
                 },
                 "protocol violation: clients may not send this message"});
    a.push_back({"wrong protocol version", [](RawClient& c) { c.send(jp::Hello{0xFFFF, "old", {}, {}}); },
                 "protocol version 65535 not supported"});
    a.push_back({"silence", [](RawClient&) {}, "no hello within"});
    a.push_back({"second hello",
                 [](RawClient& c) {
                     c.send(jp::Hello{jp::kProtocolVersion, "twice", {}, {}});
                     c.send(jp::Hello{jp::kProtocolVersion, "twice", {}, {}});
                 },
                 "protocol violation: second hello"});
    return a;
}

bool answered(const Attack& a) { return !a.client->goodbye.empty() || !a.client->refuse.empty(); }

TEST(Hostile, JunkOutOfOrderImpostorAndTooManyPlayersChangeNothing) {
    LogCapture log;
    LiveRaceOptions o = honest_options();  // the spare slot: the second hello, then the impostor
    o.hello_timeout_s = 3.0;
    o.spare_connections = 24;  // every attacker connects at once
    LiveRace race(o);
    ASSERT_TRUE(race.ok()) << race.error;
    std::vector<Attack> attacks = junk_attacks(jetrace::test::test_seed(77));
    RawClient* impostor = nullptr;
    std::vector<RawClient*> extra;
    std::uint64_t impostor_inputs = 0;
    const bool ended = race.run([&] {
        if (race.server().phase() != jp::RacePhase::racing && attacks.front().client == nullptr) return;
        for (Attack& a : attacks) {
            if (a.client == nullptr) a.client = &race.add_raw();
            if (!a.done && a.client->connected) {
                a.act(*a.client);
                a.done = true;
            }
        }
        // The second hello's slot freed, an impostor named like bot 0 joins
        // (spectating: no car mid-race) and drives "its" car.
        const bool freed = answered(attacks.back());
        if (freed && impostor == nullptr) {
            impostor = &race.add_raw();
        }
        if (impostor != nullptr && impostor->connected && !impostor->welcome && impostor_inputs == 0) {
            impostor->send(jp::Hello{jp::kProtocolVersion, "bot0", {}, {}});
            impostor_inputs = 1;
        }
        if (impostor != nullptr && impostor->welcome && race.now_us() % 3000 == 0 && impostor->server_tick > 0) {
            impostor->send(full_throttle(impostor->server_tick, 16), jetrace::net::Channel::unreliable);
            ++impostor_inputs;
        }
        // Every slot now taken: three more players are refused.
        if (impostor != nullptr && impostor->welcome && extra.empty()) {
            for (int i = 0; i < 3; ++i) extra.push_back(&race.add_raw());
        }
        for (RawClient* e : extra) {
            if (e->connected && e->refuse.empty() && e->goodbye.empty() && e->snapshots == 0 && !e->welcome) {
                e->send(jp::Hello{jp::kProtocolVersion, "extra", {}, {}});
                e->snapshots = 1;  // sent (reuses the counter as a flag: no snapshots come before a welcome)
            }
        }
    });
    ASSERT_TRUE(ended) << "the race did not end in time";
    ASSERT_EQ(race.ends.size(), 1u);
    expect_every_bot_finished(race, 4);
    expect_untouched(race);

    for (const Attack& a : attacks) {
        ASSERT_NE(a.client, nullptr) << a.what;
        const std::string said = a.client->goodbye + a.client->refuse;
        EXPECT_NE(said.find(a.reason), std::string::npos) << a.what << ": the server said '" << said << "'";
        EXPECT_TRUE(log.has_line(a.reason)) << a.what << ": the log does not say '" << a.reason << "'";
    }
    EXPECT_TRUE(log.has_line("dropping client", "(no name)", "malformed message"));
    ASSERT_NE(impostor, nullptr);
    ASSERT_TRUE(impostor->welcome.has_value());
    EXPECT_EQ(impostor->welcome->slot, 4) << "the impostor got another player's slot";
    EXPECT_GT(impostor_inputs, 10u);
    EXPECT_TRUE(log.has_line("is 'bot0' in slot 4 (spectating"));
    EXPECT_TRUE(log.has_line("(bot0): inputs while spectating", "ignored"));
    ASSERT_EQ(extra.size(), 3u);
    for (RawClient* e : extra) EXPECT_EQ(e->refuse, "server full (5 players)");
    EXPECT_TRUE(log.has_line("refusing client", "(extra): server full"));
    // The metrics' counters saw the same.
    const jetrace::server::RaceCounters counted = race.server().counters();
    EXPECT_EQ(counted.refused[static_cast<std::size_t>(jetrace::server::Refusal::full)], 3u);
    EXPECT_GE(counted.dropped[static_cast<std::size_t>(jetrace::server::DropReason::malformed)], 5u);
    EXPECT_EQ(counted.races_started, 1u);
    EXPECT_EQ(counted.races_finished, 1u);
}

// Sends every InputBatch of the bot it wraps several times over: the same
// batch again, then its ticks with different inputs (full throttle), then
// its inputs claimed for the tick before. A server that stepped a car once
// per input, or took the last input for a tick, would make it faster.
class SpeedHack final : public jetrace::test::ForwardingTransport {
public:
    using ForwardingTransport::ForwardingTransport;
    bool send(jetrace::net::PeerId peer, jetrace::net::Channel ch, std::span<const std::uint8_t> data) override {
        const bool ok = inner().send(peer, ch, data);
        jp::Message m;
        std::string why;
        if (!ok || !jp::decode(data, m, why) || !std::holds_alternative<jp::InputBatch>(m)) return ok;
        const jp::InputBatch b = std::get<jp::InputBatch>(m);
        for (int i = 0; i < 3; ++i) inner().send(peer, ch, data);
        jp::InputBatch faster = full_throttle(b.first_tick, b.inputs.size());
        faster.ack_snapshot_tick = b.ack_snapshot_tick;
        inner().send(peer, ch, jp::encode(faster));
        if (b.first_tick > 0) {
            jp::InputBatch earlier = b;
            earlier.first_tick -= 1;
            inner().send(peer, ch, jp::encode(earlier));
        }
        ++batches;
        return ok;
    }

    std::uint64_t batches = 0;
};

TEST(Hostile, SeveralInputsPerTickMakeNoCarFaster) {
    LogCapture log;
    LiveRaceOptions o = honest_options();
    SpeedHack* hack = nullptr;
    o.wrap = [&](int bot, std::unique_ptr<jetrace::net::Transport> t) -> std::unique_ptr<jetrace::net::Transport> {
        if (bot != 2) return t;
        auto h = std::make_unique<SpeedHack>(std::move(t));
        hack = h.get();
        return h;
    };
    LiveRace race(o);
    ASSERT_TRUE(race.ok()) << race.error;
    ASSERT_TRUE(race.run()) << "the race did not end in time";
    ASSERT_NE(hack, nullptr);
    EXPECT_GT(hack->batches, 100u);
    ASSERT_EQ(race.ends.size(), 1u);
    expect_every_bot_finished(race, 4);
    // Every car, the cheater's included, was stepped once per tick with the
    // first input its client sent for it: no extra copy, no later
    // full-throttle claim moved it.
    expect_untouched(race);
    EXPECT_TRUE(log.has_line("(bot2): a second, different input for tick", "only the first one received counts"));
}

TEST(Hostile, InputsFarInTheFutureOrPastMoveNothing) {
    LogCapture log;
    LiveRaceOptions o;
    o.bots = 3;
    o.min_players = 4;
    o.max_players = 4;
    o.finish_window_s = 5;  // its car never finishes
    LiveRace race(o);
    ASSERT_TRUE(race.ok()) << race.error;
    RawClient& cheat = race.add_raw();
    bool said_hello = false;
    std::uint64_t sent = 0;
    jetrace::CarState at_go;
    const bool ended = race.run([&] {
        if (cheat.connected && !said_hello) {
            cheat.send(jp::Hello{jp::kProtocolVersion, "timetraveller", {}, {}});
            said_hello = true;
        }
        const auto& world = race.server().world();
        if (world.tick == world.start_tick && cheat.welcome) at_go = world.cars.at(cheat.welcome->slot);
        if (cheat.server_tick == 0 || race.now_us() % 4000 != 0) return;
        const std::uint32_t now = cheat.server_tick;
        cheat.send(full_throttle(now + 1000, 64), jetrace::net::Channel::unreliable);  // far future
        cheat.send(full_throttle(now + 300, 64), jetrace::net::Channel::unreliable);   // past the lead limit (240)
        sent += 2;
        if (now >= 400) {
            cheat.send(full_throttle(now - 400, 64), jetrace::net::Channel::unreliable);  // far past
            ++sent;
        }
    });
    ASSERT_TRUE(ended) << "the race did not end in time";
    ASSERT_TRUE(cheat.welcome.has_value());
    EXPECT_GT(sent, 1000u);
    expect_every_bot_finished(race, 3);
    ASSERT_EQ(race.end_worlds.size(), 1u);
    const jetrace::CarState& car = race.end_worlds.front().cars.at(cheat.welcome->slot);
    EXPECT_TRUE(car.active) << "the time traveller's car was removed";
    EXPECT_FALSE(car.finished);
    // An idle car is respawned at its last gate now and then, but never
    // passes one.
    EXPECT_EQ(car.next_checkpoint, at_go.next_checkpoint)
        << "the time traveller's car drove: some input far from the present was applied";
    EXPECT_EQ(car.lap, at_go.lap);
    EXPECT_TRUE(log.has_line("(timetraveller): input for tick", "ticks ahead of tick", "dropped"));
    EXPECT_EQ(race.replay_hash(), race.ends.front().state_hash);
    // Every input of the two batches ahead of the lead limit is counted
    // dropped; those far in the past are older than the input ring, so not
    // late; the time traveller's car went without inputs.
    const jetrace::server::RaceCounters counted = race.server().counters();
    EXPECT_GE(counted.inputs_dropped, 64u * sent / 2);
    EXPECT_GT(counted.inputs_missing, 1000u);
}

TEST(Faults, ClientThatVanishesMidRaceIsTimedOutAndTheRaceGoesOn) {
    LogCapture log;
    LiveRaceOptions o;
    o.laps = 2;
    o.server_timeout_ms = 1000;  // ENet's clock: real milliseconds
    LiveRace race(o);
    ASSERT_TRUE(race.ok()) << race.error;
    bool frozen = false;
    std::uint32_t removed_at = 0;
    const bool ended = race.run([&] {
        const auto& world = race.server().world();
        if (!frozen && race.server().phase() == jp::RacePhase::racing && world.tick > 600) {
            race.freeze_bot(3);  // no goodbye, no ENet disconnect: it just stops
            frozen = true;
        }
        if (frozen && removed_at == 0 && !world.cars.at(3).active) removed_at = world.tick;
    });
    ASSERT_TRUE(ended) << "the race did not end in time";
    ASSERT_TRUE(frozen);
    EXPECT_GT(removed_at, 0u) << "the silent client's car was never removed";
    EXPECT_TRUE(log.has_line("(bot3) disconnected"));
    ASSERT_EQ(race.ends.size(), 1u);
    const auto& standings = race.ends.front().standings;
    EXPECT_EQ(standings.size(), 3u);
    for (const auto& s : standings) {
        EXPECT_NE(s.name, "bot3");
        EXPECT_TRUE(s.finished) << s.name;
    }
    expect_every_bot_finished(race, 3);
    EXPECT_EQ(race.replay_hash(), race.ends.front().state_hash) << "the replay does not record the removal";
}

}  // namespace
