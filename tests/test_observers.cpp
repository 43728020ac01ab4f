// Observers (Hello.observe) against a live server (real ENet on 127.0.0.1,
// virtual clock) beside an honest 4-bot race: they take no slot, get the
// race's snapshots (delta-encoded against their acknowledgements) and
// results, and change nothing in it: every car is stepped with exactly the
// inputs its own bot sent, and the race ends in the replay of those inputs
// (support/input_audit.hpp says why not "the same race without them"). One more than
// --max-observers is refused with its close code; an observer's inputs are
// ignored.
#include "support/live_race.hpp"
#include "support/log_capture.hpp"
#include "support/respawn_window.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace {

using jetrace::test::LiveRace;
using jetrace::test::LiveRaceOptions;
namespace jp = jetrace::proto;

LiveRaceOptions honest_options() {
    LiveRaceOptions o;
    o.bots = 4;
    o.spare_connections = 24;  // room for the observers, and the one refused
    return o;
}

// The race went by its players' inputs alone: each car was stepped with
// exactly what its own bot sent, the end state is the replay of those
// inputs, and all 4 cars finished.
void expect_untouched(LiveRace& race) {
    ASSERT_EQ(race.ends.size(), 1u);
    const jetrace::server::RaceEnd& end = race.ends.front();
    EXPECT_EQ(race.replay_hash(), end.state_hash) << "the race is not the replay of its inputs";
    race.expect_cars_moved_by_their_own_bots();
    ASSERT_EQ(end.standings.size(), 4u);
    for (const auto& s : end.standings) EXPECT_TRUE(s.finished) << s.name;
}

jetrace::client::ClientConfig observer_config(const std::string& name) {
    jetrace::client::ClientConfig cc;
    cc.name = name;
    cc.observe = true;
    return cc;
}

std::size_t count_lines(const std::string& text, const std::string& part) {
    std::size_t n = 0;
    for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
    return n;
}

}  // namespace

TEST(Observers, EightChangeNothingInTheRaceAndANinthIsRefused) {
    LiveRace race(honest_options());
    ASSERT_TRUE(race.ok()) << race.error;
    constexpr int kObservers = 8;  // ServerConfig::max_observers' default
    for (int i = 0; i < kObservers; ++i) race.add_bot(observer_config("eye" + std::to_string(i)));
    jetrace::test::Bot* ninth = nullptr;
    int most_observers = 0, render_checks = 0, spans = 0;
    double max_render_gap_m = 0, max_gap_before_respawn_m = 0;
    jetrace::test::RespawnWindows respawns;  // as observer 4 sees them
    const bool ended = race.run([&] {
        const auto& server = race.server();
        most_observers = std::max(most_observers, server.observers());
        if (ninth == nullptr && server.observers() == kObservers) ninth = &race.add_bot(observer_config("one too many"));
        const auto& eye = *race.bot(4).client;
        if (server.phase() != jp::RacePhase::racing || eye.state() != jetrace::client::ClientState::racing) return;
        // What an observer draws: every active car, near its newest authoritative place.
        const jetrace::WorldState drawn = eye.render_world();
        const jetrace::WorldState& newest = eye.authoritative();
        respawns.see(newest);
        std::uint32_t from = 0, to = 0;
        if (eye.render_span(from, to)) {
            EXPECT_LE(from, eye.render_tick());
            EXPECT_GT(to, eye.render_tick());
            ++spans;
        }
        for (std::size_t s = 0; s < drawn.cars.size() && s < newest.cars.size(); ++s) {
            if (!newest.cars[s].active || newest.cars[s].finished) continue;
            EXPECT_TRUE(drawn.cars[s].active);
            EXPECT_EQ(drawn.cars[s].position, eye.visual_position(static_cast<int>(s)));
            // Until the render tick reaches the snapshot that showed a
            // respawn, the car is drawn where it was before it.
            if (respawns.drawn_before_respawn(s, eye.render_tick())) {
                max_gap_before_respawn_m = std::max(max_gap_before_respawn_m, (drawn.cars[s].position - respawns.before(s)).norm());
                continue;
            }
            max_render_gap_m = std::max(max_render_gap_m, (drawn.cars[s].position - newest.cars[s].position).norm());
            ++render_checks;
        }
    });
    ASSERT_TRUE(ended) << "the race did not end in time";
    expect_untouched(race);
    EXPECT_EQ(race.server().max_players_seen(), 4) << "an observer counted as a player";
    EXPECT_EQ(most_observers, kObservers);
    EXPECT_GT(render_checks, 100);
    EXPECT_GT(spans, 100) << "the render tick was seldom between two snapshots";
    EXPECT_LT(max_render_gap_m, 8.0);
    EXPECT_LT(max_gap_before_respawn_m, 8.0) << "a respawned car was drawn on its way to its last gate";

    const std::uint64_t player_bytes = race.bot(0).client->totals().bytes_received;
    for (int i = 4; i < 4 + kObservers; ++i) {
        const auto& eye = *race.bot(i).client;
        EXPECT_TRUE(eye.observer()) << "observer " << i - 4;
        EXPECT_EQ(eye.slot(), -1);
        EXPECT_GT(eye.stats().snapshots, 100u) << "observer " << i - 4;
        EXPECT_EQ(eye.results().race_number, 1u) << "observer " << i - 4 << " got no results";
        EXPECT_EQ(jetrace::hash_hex(eye.results().state_hash), jetrace::hash_hex(race.ends.front().state_hash));
        EXPECT_GT(eye.totals().bytes_sent, 0u) << "observer " << i - 4 << " acknowledged nothing";
        // Snapshots delta-encoded against the observer's acknowledgements
        // weigh about what a player's do; without a baseline each would be
        // several times larger.
        EXPECT_LT(eye.totals().bytes_received, player_bytes * 3 / 2) << "observer " << i - 4;
    }
    ASSERT_NE(ninth, nullptr);
    EXPECT_EQ(ninth->client->state(), jetrace::client::ClientState::closed);
    EXPECT_EQ(ninth->client->close_code(), static_cast<std::uint16_t>(jp::CloseCode::refused_observers_full))
        << ninth->client->close_reason();
    const auto refused = race.server().counters().refused;
    EXPECT_EQ(refused[static_cast<std::size_t>(jetrace::server::Refusal::observers_full)], 1u);
    EXPECT_EQ(refused[static_cast<std::size_t>(jetrace::server::Refusal::full)], 0u);
}

TEST(Observers, AnObserversInputsAreIgnored) {
    jetrace::test::LogCapture log;
    LiveRace race(honest_options());
    ASSERT_TRUE(race.ok()) << race.error;
    jetrace::test::RawClient& eye = race.add_raw();
    eye.send_on_connect(jp::Hello{jp::kProtocolVersion, "bot0", {}, {}, true});
    std::uint64_t batches = 0;
    const bool ended = race.run([&] {
        if (!eye.welcome || eye.server_tick == 0 || race.now_us() % 3000 != 0) return;
        // Full throttle for ticks the server has not stepped yet, claiming
        // the car of the player of the same name.
        jp::InputBatch b;
        b.first_tick = eye.server_tick;
        b.inputs.assign(16, jetrace::Input::clamped(15, 0, 0));
        b.ack_snapshot_tick = eye.server_tick;
        eye.send(b, jetrace::net::Channel::unreliable);
        ++batches;
    });
    ASSERT_TRUE(ended) << "the race did not end in time";
    expect_untouched(race);
    ASSERT_TRUE(eye.welcome.has_value());
    EXPECT_TRUE(eye.welcome->observer);
    EXPECT_TRUE(eye.welcome->reconnect_token.empty()) << "an observer has nothing to reconnect to";
    EXPECT_GT(batches, 100u);
    EXPECT_GT(eye.snapshots, 100u);
    EXPECT_EQ(count_lines(log.text(), "(bot0): inputs from an observer"), 1u) << "not logged exactly once";
}
