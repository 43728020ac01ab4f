// Loopback races: a real server and real clients over real ENet on
// 127.0.0.1 (ports chosen at run time), in one process, on a clock that runs
// faster than real time. Conditions (loss, latency, jitter, duplication,
// reordering) are injected in the transport on both sides.
#include "support/live_race.hpp"
#include "support/respawn_window.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <map>

namespace {

struct RaceOutcome {
    bool server_done = false;
    jetrace::server::RaceEnd end;
    std::vector<jetrace::server::RaceEnd> ends;
    std::vector<jetrace::client::ClientStats> stats;
    std::vector<bool> finished;
    std::uint64_t replay_hash = 0;
    bool replay_ok = false;
    int hash_checks = 0;
    int hash_mismatches = 0;
    /// Largest distance between where bot 0 draws bot 1 (interpolated) and
    /// bot 1's newest authoritative position, while racing and not drawing
    /// it before a respawn the newest snapshot shows (unit: m).
    double max_interpolation_gap_m = 0;
    int interpolation_checks = 0;
    /// Largest distance between where bot 0 draws bot 1 and where bot 1 was
    /// before a respawn the newest snapshot shows, until the render tick
    /// reaches that snapshot (0 if it never respawned; unit: m).
    double max_gap_before_respawn_m = 0;
    /// Most players bot 0's roster (RaceClient::players()) listed at once,
    /// and whether every entry had a name.
    std::size_t max_roster = 0;
    bool roster_named = true;
};

RaceOutcome race(int bots, const jetrace::net::Conditions* conditions, int laps, int races = 1) {
    RaceOutcome out;
    jetrace::test::LiveRaceOptions o;
    o.log_levels_from_env = true;  // SPDLOG_LEVEL=debug shows every correction
    o.bots = bots;
    o.laps = laps;
    o.races = races;
    o.spare_connections = 4;
    o.conditions = conditions;
    jetrace::test::LiveRace live(o);
    EXPECT_TRUE(live.ok()) << live.error;
    if (!live.ok()) return out;

    // Server hashes by tick, to check clients decode exactly what it had.
    std::map<std::uint32_t, std::uint64_t> server_hashes;
    jetrace::test::RespawnWindows respawns;  // as bot 0 sees them
    out.server_done = live.run(
        [&] {
            const auto& server = live.server();
            if (server.phase() == jetrace::proto::RacePhase::racing) {
                server_hashes[server.world().tick] = jetrace::state_hash(server.world());
            }
            for (int i = 0; i < bots; ++i) {
                const jetrace::WorldState& a = live.bot(i).client->authoritative();
                const auto it = server_hashes.find(a.tick);
                if (it != server_hashes.end() && a.tick > 0 && (live.now_us() / 1000) % 97 == 0) {
                    ++out.hash_checks;
                    out.hash_mismatches += jetrace::state_hash(a) != it->second ? 1 : 0;
                }
            }
            if (server_hashes.size() > 4000) server_hashes.erase(server_hashes.begin());
            const auto& roster = live.bot(0).client->players();
            out.max_roster = std::max(out.max_roster, roster.size());
            for (const auto& p : roster) out.roster_named = out.roster_named && !p.name.empty();
            if (server.phase() == jetrace::proto::RacePhase::racing && bots > 1) {
                const auto& a = live.bot(0).client->authoritative();
                respawns.see(a);
                if (a.cars.size() > 1 && a.cars[1].active && !a.cars[1].finished) {
                    const jetrace::Vec3 drawn = live.bot(0).client->visual_position(1);
                    // Until the render tick reaches the snapshot that showed
                    // a respawn, the car is drawn where it was before it.
                    if (respawns.drawn_before_respawn(1, live.bot(0).client->render_tick())) {
                        out.max_gap_before_respawn_m =
                            std::max(out.max_gap_before_respawn_m, (drawn - respawns.before(1)).norm());
                    } else {
                        out.max_interpolation_gap_m = std::max(out.max_interpolation_gap_m, (drawn - a.cars[1].position).norm());
                        ++out.interpolation_checks;
                    }
                }
            }
        },
        240.0);
    out.ends = live.ends;
    if (!live.ends.empty()) out.end = live.ends.back();
    for (int i = 0; i < bots; ++i) {
        out.stats.push_back(live.bot(i).client->stats());
        out.finished.push_back(live.finished(i));
    }
    const auto replay = live.replay_hash();
    out.replay_ok = replay.has_value();
    out.replay_hash = replay.value_or(0);
    EXPECT_TRUE(out.replay_ok) << "the replay is unreadable";
    return out;
}

void report(const RaceOutcome& o) {
    std::uint64_t snaps = 0, corr = 0, checked = 0, off = 0, unexplained = 0;
    double max_m = 0;
    for (const auto& s : o.stats) {
        snaps += s.snapshots;
        corr += s.corrections;
        checked += s.drawn_checked;
        off += s.drawn_off;
        unexplained += s.drawn_off_unexplained;
        max_m = std::max(max_m, s.max_correction_m);
    }
    std::printf("snapshots=%llu corrections=%llu max_correction_m=%.4f hash_checks=%d drawn_checked=%llu drawn_off=%llu (unexplained %llu)\n",
                static_cast<unsigned long long>(snaps), static_cast<unsigned long long>(corr), max_m, o.hash_checks,
                static_cast<unsigned long long>(checked), static_cast<unsigned long long>(off),
                static_cast<unsigned long long>(unexplained));
}

}  // namespace

TEST(Loopback, EightBotsNoLoss) {
    const RaceOutcome o = race(8, nullptr, 1);
    report(o);
    ASSERT_TRUE(o.server_done) << "the race did not end in time";
    ASSERT_EQ(o.finished.size(), 8u);
    for (std::size_t i = 0; i < o.finished.size(); ++i) EXPECT_TRUE(o.finished[i]) << "bot " << i << " did not finish";
    for (std::size_t i = 0; i < o.stats.size(); ++i) {
        EXPECT_GT(o.stats[i].snapshots, 100u) << "bot " << i;
        EXPECT_EQ(o.stats[i].corrections, 0u) << "bot " << i << " had to correct its prediction without any loss";
        // Where the bot's car was drawn: the server's position, bit for
        // bit, but near another car (a touch mispredicted, then its fading
        // offset).
        EXPECT_GT(o.stats[i].drawn_checked, 100u) << "bot " << i;
        EXPECT_EQ(o.stats[i].drawn_off_unexplained, 0u) << "bot " << i << ": drawn elsewhere than the server had it ("
                                                        << o.stats[i].drawn_off << " of " << o.stats[i].drawn_checked
                                                        << " ticks), with no car near and no late input";
    }
    EXPECT_GT(o.hash_checks, 10);
    EXPECT_EQ(o.max_roster, 8u) << "the RaceStatus roster lists every player";
    EXPECT_TRUE(o.roster_named);
    // Drawn two snapshot intervals (33 ms) behind: a car at 70-100 m/s is a
    // few metres back, never tens.
    EXPECT_GT(o.interpolation_checks, 100);
    EXPECT_LT(o.max_interpolation_gap_m, 8.0);
    EXPECT_LT(o.max_gap_before_respawn_m, 8.0) << "a respawned car was drawn on its way to its last gate";
    EXPECT_GT(o.max_interpolation_gap_m, 0.0) << "interpolation shows the newest state: no delay at all";
    EXPECT_EQ(o.hash_mismatches, 0) << "a client decoded a state whose hash differs from the server's at that tick";
    EXPECT_EQ(jetrace::hash_hex(o.replay_hash), jetrace::hash_hex(o.end.state_hash))
        << "the recorded replay does not reproduce the live server's final state";
}

TEST(Loopback, EightBotsLossLatencyJitterDuplicationReordering) {
    jetrace::net::Conditions c;
    c.latency_ms = 50;
    c.jitter_ms = 20;
    c.loss = 0.05;
    c.duplicate = 0.02;
    c.reorder = 0.02;
    c.seed = 5;
    const RaceOutcome o = race(8, &c, 1);
    report(o);
    ASSERT_TRUE(o.server_done) << "the race did not end in time";
    for (std::size_t i = 0; i < o.finished.size(); ++i) EXPECT_TRUE(o.finished[i]) << "bot " << i << " did not finish";
    std::uint64_t snaps = 0, corr = 0;
    for (const auto& s : o.stats) {
        snaps += s.snapshots;
        corr += s.corrections;
    }
    ASSERT_GT(snaps, 800u);
    // The figure: at least 99.9% of snapshots need no correction.
    EXPECT_LE(static_cast<double>(corr), 0.001 * static_cast<double>(snaps)) << "corrections are not rare";
    for (const auto& st : o.stats) EXPECT_LT(st.max_correction_m, 0.5) << "a correction did not stay small";
    EXPECT_EQ(o.hash_mismatches, 0);
    EXPECT_EQ(jetrace::hash_hex(o.replay_hash), jetrace::hash_hex(o.end.state_hash));
}

TEST(Loopback, BotsWithAnInputDelayStillPredictAheadOfTheServer) {
    // With an input delay of 4 ticks the inputs reach the server 4 ticks
    // earlier than without, and the prediction itself still runs ahead of
    // the server: the clock keeps its target margin for the predicted tick,
    // not for the newest input (which is 4 ticks further on).
    jetrace::test::LiveRaceOptions opt;
    opt.bots = 4;
    opt.input_delay_ticks = 4;
    jetrace::test::LiveRace live(opt);
    ASSERT_TRUE(live.ok()) << live.error;
    int samples = 0, ahead = 0;
    const bool done = live.run(
        [&] {
            const auto& server = live.server();
            if (server.phase() != jetrace::proto::RacePhase::racing) return;
            const std::uint32_t now = server.world().tick;
            for (int i = 0; i < live.bots(); ++i) {
                const auto& c = *live.bot(i).client;
                if (c.predicted_tick() == 0) continue;
                ++samples;
                // Ahead by the target margin (2 ticks) at least.
                ahead += c.predicted_tick() >= now + 2 ? 1 : 0;
            }
        },
        240.0);
    ASSERT_TRUE(done) << "the race did not end in time";
    for (int i = 0; i < live.bots(); ++i) {
        EXPECT_TRUE(live.finished(i)) << "bot " << i << " did not finish";
        EXPECT_EQ(live.bot(i).client->stats().corrections, 0u) << "bot " << i;
        EXPECT_EQ(live.bot(i).client->stats().late_inputs, 0u) << "bot " << i;
        // Behind the server, every snapshot would restart the clock.
        EXPECT_LT(live.bot(i).client->stats().clock_resyncs, 10u) << "bot " << i;
    }
    ASSERT_GT(samples, 1000);
    EXPECT_GT(ahead, samples * 9 / 10) << "the prediction ran less than 2 ticks ahead of the server (" << ahead << " of "
                                       << samples << " samples 2 or more ahead)";
}

TEST(Loopback, TwoRacesInARow) {
    // Clients stay connected for a second race: a fresh world whose ticks
    // start again from 0 must not confuse their input or snapshot state.
    const RaceOutcome o = race(3, nullptr, 1, 2);
    report(o);
    ASSERT_TRUE(o.server_done);
    ASSERT_EQ(o.ends.size(), 2u);
    for (const auto& e : o.ends) {
        ASSERT_FALSE(e.standings.empty());
        for (const auto& s : e.standings) EXPECT_TRUE(s.finished) << "race " << e.race_number << " slot " << int{s.slot};
    }
    const double first = o.ends[0].standings[0].finish_time_s;
    const double second = o.ends[1].standings[0].finish_time_s;
    EXPECT_LT(second, first * 1.3) << "the second race's winner was much slower: inputs lost after the restart?";
    for (const auto& st : o.stats) EXPECT_EQ(st.corrections, 0u);
}

TEST(Loopback, LongLatencyTheClientsClockDidNotExpect) {
    // 100 ms each way on the virtual clock while ENet measures a loopback
    // round trip of about 0 ms: every client starts far too little ahead and
    // must jump. Jumping again on every snapshot before the first jump shows
    // in the feedback would overshoot by hundreds of ticks.
    jetrace::net::Conditions c;
    c.latency_ms = 100;
    c.seed = 9;
    const RaceOutcome o = race(4, &c, 1);
    report(o);
    ASSERT_TRUE(o.server_done) << "the race did not end in time";
    for (std::size_t i = 0; i < o.finished.size(); ++i) EXPECT_TRUE(o.finished[i]) << "bot " << i << " did not finish";
}

TEST(Loopback, ResultsReachEveryClientBeforeTheServerExits) {
    // jetrace-server exits once done(). Its Results and Goodbye leave behind
    // 100 ms of latency (each way): done() must wait until every client has
    // them (its connection closed), not turn true as the last race ends.
    jetrace::net::Conditions c;
    c.latency_ms = 100;
    c.seed = 13;
    jetrace::test::LiveRaceOptions o;
    o.bots = 4;
    o.conditions = &c;
    o.record = false;
    o.log_levels_from_env = true;
    jetrace::test::LiveRace live(o);
    ASSERT_TRUE(live.ok()) << live.error;
    ASSERT_TRUE(live.run_until([&] { return live.server().done(); }, 300000)) << "the race did not end";
    ASSERT_EQ(live.ends.size(), 1u);
    live.close_server();
    live.run_until([] { return false; }, 2000);
    for (int i = 0; i < live.bots(); ++i) {
        const auto& client = *live.bot(i).client;
        EXPECT_EQ(client.results().race_number, 1u) << "bot " << i << " never got the Results";
        EXPECT_EQ(client.close_code(), static_cast<std::uint16_t>(jetrace::proto::CloseCode::server_shutdown))
            << "bot " << i << " lost the server instead of hearing its Goodbye: " << client.close_reason();
    }
}
